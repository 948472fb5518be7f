#pragma once
// A run's folder (--out or --resume) of the programs that write one (biaxial, element_test):
// what a run writes there, the lock that keeps a second run out while one runs, the claim of a
// folder for a new run, and the run id that ties a folder's files to one run.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <micromacro/core/error.hpp>

namespace micromacro::cli {

namespace fs = std::filesystem;

/// What a run writes into its folder. A folder that holds any of these holds a run.
inline constexpr const char* run_entries[] = {"run.json",       "timeseries.csv", "timeseries.csv.partial", "checkpoint.state",
                                              "prepared.state", "vtk",            "plots",                  "snapshots",
                                              "movie.mp4",      "movie_frames",   "probes.csv"};

/// The folder's lock, held for the whole run by the process that writes the files: a second run
/// into the same folder (or a --resume of it) is refused while the first runs. The kernel lets go
/// of it when the process ends in any way, so a killed run leaves no stale lock. The lock file
/// (`.lock`, the holder's process id) stays; it is not a run's entry.
class FolderLock {
public:
    FolderLock() = default;
    FolderLock(const FolderLock&) = delete;
    FolderLock& operator=(const FolderLock&) = delete;
    ~FolderLock() {
        if (fd_ >= 0) ::close(fd_);
    }

    /// Takes the lock of `folder` (which exists), or refuses with the process that holds it
    /// (a run of `program`, given by `option`).
    void take(const fs::path& folder, const std::string& option, const std::string& program) {
        const fs::path file = folder / ".lock";
        fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0)
            micromacro::throw_input_error(option, " ", folder.string(), " is not a writable directory (its lock file ",
                                          file.string(), ": ", std::strerror(errno), ")");
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            std::string holder;
            std::ifstream(file) >> holder;
            ::close(fd_);
            fd_ = -1;
            micromacro::throw_input_error(option, " ", folder.string(), " is in use by another ", program, " run",
                                          holder.empty() ? "" : " (process " + holder + ")",
                                          "; wait for it to finish, or give another --out");
        }
        const std::string pid = std::to_string(::getpid()) + "\n";
        if (::ftruncate(fd_, 0) != 0 || ::write(fd_, pid.data(), pid.size()) != static_cast<ssize_t>(pid.size()))
            micromacro::throw_input_error("cannot write the lock file ", file.string(), " (disk full?)");
    }

private:
    int fd_ = -1;
};

/// The run entries `out` holds, listed with commas (empty: none).
inline std::string run_entries_in(const fs::path& out) {
    std::string found;
    for (const char* entry : run_entries)
        if (fs::exists(out / entry)) found += (found.empty() ? "" : ", ") + std::string(entry);
    return found;
}

/// Makes `out` ready for a new run: created if missing, locked for this run (writing the lock file
/// shows the folder writable). A folder that holds an earlier run is refused, so that no result is
/// overwritten and no two runs mix, unless `overwrite`, which first removes that run's entries (and
/// nothing else of the folder).
inline void claim_output_folder(const fs::path& out, bool overwrite, const std::string& from_prepared, FolderLock& lock,
                                const std::string& program) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec || !fs::is_directory(out)) micromacro::throw_input_error("--out ", out.string(), " is not a writable directory");
    lock.take(out, "--out", program);
    if (const std::string found = run_entries_in(out); !found.empty()) {
        if (!overwrite)
            micromacro::throw_input_error("--out ", out.string(), " holds an earlier run (", found,
                                          "); give another --out, --resume ", out.string(),
                                          " to continue a killed run, or --overwrite to replace it");
        if (!from_prepared.empty() && fs::weakly_canonical(from_prepared, ec).parent_path() == fs::weakly_canonical(out, ec))
            micromacro::throw_input_error("--from-prepared ", from_prepared, " lies in --out ", out.string(),
                                          ", which --overwrite would clear first; copy it elsewhere or choose another --out");
        for (const char* entry : run_entries) fs::remove_all(out / entry);
    }
}

/// After a failed run: its time series is removed unless a checkpoint can resume it, so that a
/// half-written series is neither left behind nor taken for a run (the folder's prepared state, if
/// the preparation finished, and its VTK frames stay: they are whole).
inline void discard_unresumable_series(const fs::path& out) {
    std::error_code ec;
    if (!out.empty() && !fs::exists(out / "checkpoint.state", ec)) fs::remove(out / "timeseries.csv.partial", ec);
}

/// A name for one run, written into its run.json, states and time series, so that files of two
/// runs are never taken for one: 16 hexadecimal digits from the system's random source.
inline std::string new_run_id() {
    std::random_device source;
    char id[17];
    std::snprintf(id, sizeof id, "%08x%08x", source(), source());
    return id;
}

/// The present time in UTC, as run.json states when a run started and ended.
inline std::string now_iso() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

/// A number as the time series write it: every digit a double needs to be read back exactly.
inline std::string csv_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/// The run id a time series was started with (its first line), or empty.
inline std::string run_id_of_series(const fs::path& csv) {
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    const std::string tag = "# run ";
    return line.rfind(tag, 0) == 0 ? line.substr(tag.size()) : "";
}

}  // namespace micromacro::cli
