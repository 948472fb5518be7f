#pragma once
// 64-bit FNV-1a checksums: of the state files (io/state.hpp) and of the first bytes of any file
// (a program's time series, which a resumed run continues only if it is what its checkpoint saw).
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "micromacro/core/error.hpp"

namespace micromacro::io {

/// 64-bit FNV-1a, continued over successive pieces. Any change confined to one byte changes it
/// (each step is a bijection of the running value); other changes go unseen with chance 2^-64.
struct Checksum {
    std::uint64_t value = 14695981039346656037ull;
    void add(const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t k = 0; k < n; ++k) value = (value ^ b[k]) * 1099511628211ull;
    }
};

/// The checksum of the first `bytes` bytes of `path`; refused if the file is shorter.
inline std::uint64_t checksum_of_file(const std::filesystem::path& path, std::uint64_t bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_input_error("cannot open ", path.string());
    Checksum sum;
    std::vector<char> chunk(1 << 16);
    for (std::uint64_t done = 0; done < bytes;) {
        const auto n = static_cast<std::streamsize>(std::min<std::uint64_t>(chunk.size(), bytes - done));
        in.read(chunk.data(), n);
        if (in.gcount() != n) throw_input_error(path.string(), " holds fewer than ", bytes, " bytes");
        sum.add(chunk.data(), static_cast<std::size_t>(n));
        done += static_cast<std::uint64_t>(n);
    }
    return sum.value;
}

}  // namespace micromacro::io
