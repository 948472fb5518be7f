#pragma once
// Writing a file whole or not at all: the content goes to `path`.partial, which is renamed to
// `path` only when every byte was written; a failed write removes it and throws, and an earlier
// file at `path` stays as it was until the rename. The state files, the packing dumps, the .pvd
// collections and the programs' own files (run.json) use it.
#include <filesystem>
#include <fstream>
#include <string_view>
#include <system_error>

#include "micromacro/core/error.hpp"

namespace micromacro::io {

/// Calls write(stream) on a stream to `path`.partial opened with `mode`, then renames it to `path`.
template <class Write>
void write_whole_file(const std::filesystem::path& path, std::ios::openmode mode, Write&& write) {
    const std::filesystem::path partial = path.string() + ".partial";
    {
        std::ofstream out(partial, mode);
        if (!out) throw_input_error("cannot write ", partial.string(), "; check the directory");
        write(out);
        out.flush();
        if (!out) {
            out.close();
            std::error_code ignored;
            std::filesystem::remove(partial, ignored);
            throw_input_error("cannot write ", partial.string(), " (disk full?)");
        }
    }
    std::error_code ec;
    std::filesystem::rename(partial, path, ec);
    if (ec) {
        std::error_code ignored;
        std::filesystem::remove(partial, ignored);
        throw_input_error("cannot rename ", partial.string(), " to ", path.string(), ": ", ec.message());
    }
}

/// `text` as the whole content of `path`, written as above.
inline void write_whole_file(const std::filesystem::path& path, std::string_view text) {
    write_whole_file(path, std::ios::out, [&](std::ofstream& out) { out << text; });
}

}  // namespace micromacro::io
