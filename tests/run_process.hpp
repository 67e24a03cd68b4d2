// Runs a program as a real child process (fork/exec, no shell) with its stdout and stderr
// captured, for the tests that drive `kerf` and the other executables from outside. Shared by
// tests/mesh/cli_test.cpp and tests/cut/cli_test.cpp.
#pragma once

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace kerf::test {

/// What a finished child left: its exit code (-1 when killed by a signal) and its output.
struct ProcessRun {
    int exit_code = -1;
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

/// Runs `exe args...`, waits for it; stdout and stderr go through `scratch_dir`/stdout|stderr.
inline ProcessRun run_process(const std::string& exe, std::vector<std::string> args,
                              const std::filesystem::path& scratch_dir) {
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
    ::waitpid(pid, &status, 0);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

}  // namespace kerf::test
