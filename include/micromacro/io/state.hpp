#pragma once
// Saving and restoring a complete simulation state (a prepared packing, a checkpoint). The file
// is binary, for this machine's byte order and this build's types: a header with a magic word,
// a format version, the kind of state (the caller's word: "prepared", "checkpoint"), a signature
// of the scene's storage and the caller's text, then every array the simulation visits in
// serialize(), then a 64-bit FNV-1a checksum of all that. A load verifies the checksum before it
// reads anything, so a file changed after it was written (a flipped byte, an edited text, a
// truncation) is refused instead of restored; then the kind, the scene and what was restored
// (Simulation::check_restored). Files are written whole to a temporary name and renamed, so a
// crash never leaves a half-written state behind.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "micromacro/core/error.hpp"
#include "micromacro/io/checksum.hpp"
#include "micromacro/io/whole_file.hpp"

namespace micromacro::io {

namespace detail {
inline constexpr char state_magic[] = "MICROMACRO-STATE";
// 2: the kind of state; a checksum at the end
// 3: tangential springs with the start of their next step (the half-step velocity)
// 4: a sliding spring's trial force (for the step that finds its contact open)
// 5: wall motions by name
// 6: 2D tangential springs without alignment padding (40-byte records); particle ids; the
//    engine's spatial sorting (count, reference distance, on/off)
// 7: walls' shapes in the scene signature
// 8: 2D tangential springs as components along the tangent (24-byte records)
// 9: forces and torques in double whatever the storage precision
// 10: the box's Lees-Edwards lattice and velocity gradient
inline constexpr std::uint32_t state_version = 10;

class StateWriter {
public:
    explicit StateWriter(std::ofstream& out) : out_(out) {}
    void raw_bytes(const void* p, std::size_t n) {
        checksum_.add(p, n);
        out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    }
    std::uint64_t checksum() const { return checksum_.value; }
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
    Checksum checksum_;
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
    /// Bytes read so far.
    std::uint64_t position() { return static_cast<std::uint64_t>(in_.tellg()); }

private:
    std::ifstream& in_;
    std::string path_;
};

/// Refuses a file that is not a state or whose checksum does not match its contents; returns the
/// size of the contents (the file less its checksum).
inline std::uint64_t verify_state_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) micromacro::detail::throw_input_error("cannot open the state file ", path.string());
    char magic[sizeof state_magic] = {};
    in.read(magic, sizeof magic);
    if (in.gcount() != static_cast<std::streamsize>(sizeof magic) || std::memcmp(magic, state_magic, sizeof magic) != 0)
        micromacro::detail::throw_input_error(path.string(), " is not a micromacro state file (it is truncated or has no ",
                                              "state header)");
    const std::uint64_t size = std::filesystem::file_size(path);
    if (size < sizeof magic + sizeof(std::uint32_t) + sizeof(std::uint64_t))
        micromacro::detail::throw_input_error(path.string(), ": the state file is truncated or damaged");
    const std::uint64_t contents = size - sizeof(std::uint64_t);
    const std::uint64_t sum = checksum_of_file(path, contents);  // the magic word included
    in.seekg(static_cast<std::streamoff>(contents));
    std::uint64_t stored = 0;
    in.read(reinterpret_cast<char*>(&stored), sizeof stored);
    if (!in || stored != sum)
        micromacro::detail::throw_input_error(path.string(), ": the state file is damaged (its checksum does not match its ",
                                              "contents: it was truncated, edited or corrupted after it was written); use ",
                                              "another copy or make it again");
    return contents;
}

/// A signature of the scene's storage: dimension, storage precision, the walls' shape, size of
/// the simulation object and of its contact history. A state saved by a different scene type is
/// refused.
template <class Sim>
std::string signature() {
    std::string walls = "none";
    if constexpr (Sim::has_walls) walls = std::remove_cvref_t<decltype(std::declval<const Sim&>().walls())>::ShapeType::name;
    return "dim=" + std::to_string(Sim::dimension) + " real=" + std::to_string(8 * sizeof(typename Sim::Scalar)) + "bit" +
           " rotation=" + std::to_string(Sim::rotation) + " walls=" + walls +
           " history=" + std::to_string(sizeof(typename Sim::History)) + " object=" + std::to_string(sizeof(Sim));
}
}  // namespace detail

/// Saves the simulation and `extra` (any text the program wants back, e.g. its settings as JSON)
/// as a state of the given kind (a word load_state can insist on, e.g. "prepared", "checkpoint").
template <class Sim>
void save_state(Sim& sim, const std::filesystem::path& path, std::string extra = {}, std::string kind = "state") {
    write_whole_file(path, std::ios::binary, [&](std::ofstream& out) {
        detail::StateWriter w(out);
        w.raw_bytes(detail::state_magic, sizeof detail::state_magic);
        std::uint32_t version = detail::state_version;
        w.raw(version);
        std::vector<char> kind_text(kind.begin(), kind.end());
        w.array(kind_text);
        const std::string signature = detail::signature<Sim>();
        std::vector<char> sig(signature.begin(), signature.end());
        w.array(sig);
        std::vector<char> text(extra.begin(), extra.end());
        w.array(text);
        sim.serialize(w);
        std::uint64_t checksum = w.checksum();
        out.write(reinterpret_cast<const char*>(&checksum), sizeof checksum);
    });
}

namespace detail {
struct StateHeader {
    std::string kind, signature, text;
};

// Reads the header after the magic word is known to be there (verify_state_file); with a
// non-empty `kind`, refuses a state of another kind.
inline StateHeader read_state_header(StateReader& r, const std::filesystem::path& path, const std::string& kind) {
    char magic[sizeof detail::state_magic] = {};
    r.raw_bytes(magic, sizeof magic);
    if (std::memcmp(magic, detail::state_magic, sizeof magic) != 0)
        micromacro::detail::throw_input_error(path.string(), " is not a micromacro state file");
    std::uint32_t version = 0;
    r.raw(version);
    if (version != detail::state_version)
        micromacro::detail::throw_input_error(path.string(), " has state format ", version, ", this build reads ",
                                              detail::state_version);
    std::vector<char> kind_text, sig, text;
    r.array(kind_text);
    r.array(sig);
    r.array(text);
    StateHeader header{{kind_text.begin(), kind_text.end()}, {sig.begin(), sig.end()}, {text.begin(), text.end()}};
    if (!kind.empty() && header.kind != kind)
        micromacro::detail::throw_input_error(path.string(), " is a ", header.kind, " state, not a ", kind, " state");
    return header;
}
}  // namespace detail

/// The extra text saved with a state, without restoring it (e.g. to learn which scene to build),
/// after the checksum and, when `kind` is given, the kind are verified.
inline std::string state_text(const std::filesystem::path& path, const std::string& kind = {}) {
    detail::verify_state_file(path);
    std::ifstream in(path, std::ios::binary);
    detail::StateReader r(in, path.string());
    const auto header = detail::read_state_header(r, path, kind);
    return header.text;
}

/// Restores a state saved by save_state into `sim` and returns the extra text. Refuses a damaged
/// file (checksum), one of another format, version, kind (when `kind` is given) or scene (for
/// example the other dimension), naming both, and restored contents that do not hold together.
template <class Sim>
std::string load_state(Sim& sim, const std::filesystem::path& path, const std::string& kind = {}) {
    const std::uint64_t contents = detail::verify_state_file(path);
    std::ifstream in(path, std::ios::binary);
    detail::StateReader r(in, path.string());
    const auto header = detail::read_state_header(r, path, kind);
    const std::string wanted = detail::signature<Sim>();
    if (header.signature != wanted)
        micromacro::detail::throw_input_error(path.string(), " holds a different scene (", header.signature, ") than this run (",
                                              wanted, ")");
    Sim restored = sim;  // restored apart, so that a refused file leaves `sim` as it was
    restored.serialize(r);
    if (r.position() != contents)
        micromacro::detail::throw_input_error(path.string(), ": the state file is damaged (its arrays do not end where its ",
                                              "checksum begins)");
    restored.check_restored(path.string());
    sim = std::move(restored);
    return header.text;
}

}  // namespace micromacro::io
