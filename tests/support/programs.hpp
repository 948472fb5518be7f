#pragma once
// Running a program of the project from a test: its exit status and what it printed.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../../examples/installed.hpp"

namespace mmtest {

using ::installed;  // whether a program the tests call (ffmpeg, xvfb-run) is on the PATH

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Writes `text` to the file `name` in `dir` (created if needed) and returns its path: the input
/// files the tests hand to programs and readers.
inline std::string write_file(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path.string();
}

/// A fresh, empty work folder of this test process under the system's temporary folder: `name`
/// plus the process id, so that two test processes (two builds tested at once, say) never share
/// one. Removed when the object goes: at the end of the process for one at namespace scope.
struct WorkFolder {
    std::filesystem::path path;
    explicit WorkFolder(const std::string& name)
        : path(std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~WorkFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    WorkFolder(const WorkFolder&) = delete;
    WorkFolder& operator=(const WorkFolder&) = delete;
};

struct ProgramResult {
    int status;     ///< as std::system returns it: 0 for success
    std::string out, err;
    /// The program's exit status (WEXITSTATUS), or -1 if it did not exit normally.
    int exit_code() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
};

/// Runs `program args` with standard output and error captured in files under `work`.
inline ProgramResult run_program(const std::string& program, const std::string& args, const std::filesystem::path& work) {
    std::filesystem::create_directories(work);
    const auto out = work / "stdout.txt", err = work / "stderr.txt";
    const int status = std::system((program + " " + args + " > " + out.string() + " 2> " + err.string()).c_str());
    return {status, slurp(out), slurp(err)};
}

/// Whether this machine lets a test mount a small file system of its own (a tmpfs in a private
/// mount namespace, `unshare -rm`, which needs no root where user namespaces are allowed, as on
/// Debian 12), for runs on a full disk.
inline bool can_fill_a_disk() {
    static const bool can = std::system("unshare -rm sh -c 'mount -t tmpfs -o size=16k tmpfs /mnt' > /dev/null 2>&1") == 0;
    return can;
}

/// Runs `program args` with `folder` (created, emptied) on a file system of `kilobytes` of its
/// own, so that the program meets a full disk there; the folder is empty again afterwards (the
/// file system goes with the namespace), except for what `keep` (a shell command run inside, e.g.
/// "ls -R folder > list") saves elsewhere. `launcher` goes before it all (xvfb-run, whose X server
/// then runs outside the namespace).
inline ProgramResult run_on_a_small_disk(const std::string& program, const std::string& args, const std::filesystem::path& folder,
                                         int kilobytes, const std::filesystem::path& work, const std::string& keep = "true",
                                         const std::string& launcher = "") {
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const std::string inside = "mount -t tmpfs -o size=" + std::to_string(kilobytes) + "k tmpfs " + folder.string() + " && " + program +
                               " " + args + "; status=$?; " + keep + "; exit $status";
    std::string quoted;
    for (char ch : inside) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return run_program(launcher + (launcher.empty() ? "" : " ") + "unshare -rm sh -c '" + quoted + "'", "", work);
}

}  // namespace mmtest
