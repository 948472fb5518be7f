#pragma once
// Saving and restoring a complete simulation state (a prepared packing, a checkpoint). The file
// is binary, for this machine's byte order and this build's types: a header with a magic word,
// a format version, the dimension and a signature of the scene's storage, then every array the
// simulation visits in serialize(). Files are written whole to a temporary name and renamed,
// so a crash never leaves a half-written state behind.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>

#include "micromacro/core/error.hpp"

namespace micromacro::io {

namespace detail {
inline constexpr char state_magic[] = "MICROMACRO-STATE";
// 2: tangential springs stored half a step ahead, with a flag for contacts already evaluated
inline constexpr std::uint32_t state_version = 2;

class StateWriter {
public:
    explicit StateWriter(std::ofstream& out) : out_(out) {}
    void raw_bytes(const void* p, std::size_t n) { out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n)); }
    template <class T>
    void raw(T& v) { raw_bytes(&v, sizeof v); }
    template <class T>
    void value(T& v) { raw(v); }
    template <class T>
    void array(std::vector<T>& v) {
        std::uint64_t n = v.size();
        raw(n);
        if (n) raw_bytes(v.data(), n * sizeof(T));
    }
    template <class M, class Variant>
    M restored(Variant& v) { M m = std::get<M>(v); raw(m); return m; }

private:
    std::ofstream& out_;
};

class StateReader {
public:
    StateReader(std::ifstream& in, std::string path) : in_(in), path_(std::move(path)) {}
    void raw_bytes(void* p, std::size_t n) {
        in_.read(static_cast<char*>(p), static_cast<std::streamsize>(n));
        if (static_cast<std::size_t>(in_.gcount()) != n)
            micromacro::detail::throw_input_error(path_, ": the state file is truncated or damaged");
    }
    template <class T>
    void raw(T& v) { raw_bytes(&v, sizeof v); }
    template <class T>
    void value(T& v) { raw(v); }
    template <class T>
    void array(std::vector<T>& v) {
        std::uint64_t n = 0;
        raw(n);
        if (n > (std::uint64_t{1} << 40) / sizeof(T))
            micromacro::detail::throw_input_error(path_, ": the state file is damaged (an array of ", n, " entries)");
        v.resize(n);
        if (n) raw_bytes(v.data(), n * sizeof(T));
    }
    template <class M, class Variant>
    M restored(Variant&) { M m{}; raw(m); return m; }

private:
    std::ifstream& in_;
    std::string path_;
};

/// A signature of the scene's storage: dimension, storage precision, size of the simulation
/// object and of its contact history. A state saved by a different scene type is refused.
template <class Sim>
std::string signature() {
    return "dim=" + std::to_string(Sim::dimension) + " real=" + std::to_string(8 * sizeof(typename Sim::Scalar)) + "bit" +
           " rotation=" + std::to_string(Sim::rotation) +
           " walls=" + std::to_string(Sim::has_walls) + " history=" + std::to_string(sizeof(typename Sim::History)) +
           " object=" + std::to_string(sizeof(Sim));
}
}  // namespace detail

/// Saves the simulation and `extra` (any text the program wants back, e.g. its settings as JSON).
template <class Sim>
void save_state(Sim& sim, const std::filesystem::path& path, std::string extra = {}) {
    const std::filesystem::path partial = path.string() + ".partial";
    {
        std::ofstream out(partial, std::ios::binary);
        if (!out) micromacro::detail::throw_input_error("cannot write ", partial.string(), "; check the directory");
        detail::StateWriter w(out);
        w.raw_bytes(detail::state_magic, sizeof detail::state_magic);
        std::uint32_t version = detail::state_version;
        w.raw(version);
        const std::string signature = detail::signature<Sim>();
        std::vector<char> sig(signature.begin(), signature.end());
        w.array(sig);
        std::vector<char> text(extra.begin(), extra.end());
        w.array(text);
        sim.serialize(w);
        out.flush();
        if (!out) {
            out.close();
            std::filesystem::remove(partial);
            micromacro::detail::throw_input_error("cannot write ", partial.string(), " (disk full?)");
        }
    }
    std::filesystem::rename(partial, path);
}

namespace detail {
struct StateHeader {
    std::string signature, text;
};

inline StateHeader read_state_header(StateReader& r, const std::filesystem::path& path) {
    char magic[sizeof detail::state_magic] = {};
    r.raw_bytes(magic, sizeof magic);
    if (std::memcmp(magic, detail::state_magic, sizeof magic) != 0)
        micromacro::detail::throw_input_error(path.string(), " is not a micromacro state file");
    std::uint32_t version = 0;
    r.raw(version);
    if (version != detail::state_version)
        micromacro::detail::throw_input_error(path.string(), " has state format ", version, ", this build reads ",
                                              detail::state_version);
    std::vector<char> sig, text;
    r.array(sig);
    r.array(text);
    return {{sig.begin(), sig.end()}, {text.begin(), text.end()}};
}
}  // namespace detail

/// The extra text saved with a state, without restoring it (e.g. to learn which scene to build).
inline std::string state_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) micromacro::detail::throw_input_error("cannot open the state file ", path.string());
    detail::StateReader r(in, path.string());
    return detail::read_state_header(r, path).text;
}

/// Restores a state saved by save_state into `sim` and returns the extra text. Refuses files of
/// another format, version or scene (for example the other dimension), naming both.
template <class Sim>
std::string load_state(Sim& sim, const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) micromacro::detail::throw_input_error("cannot open the state file ", path.string());
    detail::StateReader r(in, path.string());
    const auto header = detail::read_state_header(r, path);
    const std::string wanted = detail::signature<Sim>();
    if (header.signature != wanted)
        micromacro::detail::throw_input_error(path.string(), " holds a different scene (", header.signature, ") than this run (",
                                              wanted, ")");
    sim.serialize(r);
    return header.text;
}

}  // namespace micromacro::io
