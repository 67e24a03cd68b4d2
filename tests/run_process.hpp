// Runs a program as a real child process (fork/exec, no shell) with its stdout and stderr
// captured and a time limit (a hang is a failure, reported as exit code -2, not a stuck test),
// for every test that drives `kerf` and the other executables from outside.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace kerf::test {

/// What a finished child left: its exit code and its output.
struct ProcessRun {
    int exit_code = -1;  ///< exit status; 128+signal if killed by one; -2 if it hung
    std::string out;
    std::string err;
};

/// The whole content of a file ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs `exe args...`, waits for it (killed after `limit`); stdout and stderr go through
/// `scratch_dir`/stdout|stderr.
inline ProcessRun run_process(const std::string& exe, std::vector<std::string> args,
                              const std::filesystem::path& scratch_dir,
                              std::chrono::seconds limit = std::chrono::seconds(120)) {
    const std::filesystem::path out = scratch_dir / "stdout", err = scratch_dir / "stderr";
    std::string bin = exe;
    std::vector<char*> argv{bin.data()};
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(o, 1);
        ::dup2(e, 2);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    int status = 0;
    bool hung = false;
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            hung = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ProcessRun r{WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), slurp(out),
                 slurp(err)};
    if (hung) r.exit_code = -2;
    return r;
}

/// Runs `program` from KERF_BIN_DIR in `dir` (its stdout/stderr files go there).
inline ProcessRun run_program(const std::filesystem::path& dir, const std::string& program,
                              std::vector<std::string> args,
                              std::chrono::seconds limit = std::chrono::seconds(30)) {
    return run_process(std::string(KERF_BIN_DIR) + "/" + program, std::move(args), dir, limit);
}

}  // namespace kerf::test
