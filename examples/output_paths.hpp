#pragma once
// A program never writes over one of its own inputs: `render_snapshot p.vtp -o p.vtp` would
// replace the particles by a picture. Every program that writes checks each file it will write
// against each file it reads, before it reads or writes anything.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <micromacro/core/error.hpp>

namespace micromacro::cli {

/// Whether two paths name one file: the same existing file (through links too), or, for a file
/// still to be made, the same path once absolute and normal.
inline bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ec;
    if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
    return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
}

/// A file a program reads, and how the user gave it ("the input", "--walls").
struct Input {
    std::string given_as;
    std::filesystem::path path;
};

/// Refuses to write `output` (given as `option`) when it is one of `inputs` (empty paths are
/// skipped: options not given).
inline void refuse_writing_over_inputs(const std::filesystem::path& output, const std::string& option,
                                       const std::vector<Input>& inputs) {
    if (output.empty()) return;
    for (const auto& input : inputs)
        if (!input.path.empty() && same_file(output, input.path))
            throw_input_error(option, " ", output.string(), " is ", input.given_as, " ", input.path.string(),
                              ", which this program reads: writing it would destroy the input; give another ", option);
}

}  // namespace micromacro::cli
