// Real processes for the display's integration tests: spawn with stdout+stderr to a file, wait
// with a timeout, kill; and a scratch folder holding a kerf.toml whose scene is two tubes.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace kerf::display::test {

/// Polls `done` every 10 ms until it is true or `timeout_s` passes (generous: CI is loaded).
inline bool wait_for(const std::function<bool()>& done, double timeout_s) {
    const auto until = std::chrono::steady_clock::now() +
                       std::chrono::milliseconds(static_cast<std::int64_t>(timeout_s * 1000));
    while (!done()) {
        if (std::chrono::steady_clock::now() > until) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
}

inline std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// One child process; killed (SIGKILL) and reaped when the object dies if still running.
class Child {
public:
    Child(const std::vector<std::string>& args, std::string output_path)
        : out_(std::move(output_path)) {
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 1, out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        posix_spawn_file_actions_adddup2(&fa, 1, 2);
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        if (posix_spawn(&pid_, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&fa);
    }
    ~Child() {
        if (running()) kill(SIGKILL);
        (void)wait_exit(10);
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    bool started() const { return pid_ > 0; }
    bool running() const { return pid_ > 0 && !status_; }
    void kill(int signal) const {
        if (running()) ::kill(pid_, signal);
    }
    /// The exit status (WEXITSTATUS, or 128 + signal), or nothing after `timeout_s`.
    std::optional<int> wait_exit(double timeout_s) {
        if (pid_ <= 0) return std::nullopt;
        wait_for(
            [&] {
                if (status_) return true;
                int st = 0;
                if (waitpid(pid_, &st, WNOHANG) == pid_)
                    status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
                return status_.has_value();
            },
            timeout_s);
        return status_;
    }
    std::string output() const { return read_file(out_); }
    /// True once the child's output contains `text`.
    bool wait_output(const std::string& text, double timeout_s) const {
        return wait_for([&] { return output().find(text) != std::string::npos; }, timeout_s);
    }

private:
    pid_t pid_ = -1;
    std::optional<int> status_;
    std::string out_;
};

inline std::string bin(const char* name) { return std::string(KERF_BIN_DIR) + "/" + name; }

}  // namespace kerf::display::test
