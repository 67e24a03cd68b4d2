#include "tools/supervise/child_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <thread>

extern char** environ;

namespace kerf::supervise {

std::string_view to_string(SpawnErrc code) noexcept {
    switch (code) {
        case SpawnErrc::kNotExecutable:
            return "not_executable";
        case SpawnErrc::kLogFile:
            return "log_file";
        case SpawnErrc::kSpawnFailed:
            return "spawn_failed";
    }
    return "unknown";
}

bool ExitInfo::exited() const noexcept { return WIFEXITED(wait_status); }
int ExitInfo::exit_code() const noexcept { return WEXITSTATUS(wait_status); }
int ExitInfo::term_signal() const noexcept {
    return WIFSIGNALED(wait_status) ? WTERMSIG(wait_status) : 0;
}

std::string ExitInfo::describe() const {
    if (exited()) return "exited " + std::to_string(exit_code());
    const char* abbrev = sigabbrev_np(term_signal());
    return std::string("killed by SIG") + (abbrev ? abbrev : std::to_string(term_signal()).c_str());
}

namespace {

/// posix_spawn attributes: own process group, default dispositions for the signals a
/// supervisor catches, an empty signal mask.
struct SpawnAttributes {
    posix_spawnattr_t attr;
    SpawnAttributes() {
        posix_spawnattr_init(&attr);
        sigset_t defaults;
        sigemptyset(&defaults);
        for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGCHLD, SIGPIPE, SIGQUIT})
            sigaddset(&defaults, sig);
        sigset_t empty;
        sigemptyset(&empty);
        posix_spawnattr_setsigdefault(&attr, &defaults);
        posix_spawnattr_setsigmask(&attr, &empty);
        posix_spawnattr_setpgroup(&attr, 0);
        posix_spawnattr_setflags(
            &attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
    }
    ~SpawnAttributes() { posix_spawnattr_destroy(&attr); }
};

struct FileActions {
    posix_spawn_file_actions_t actions;
    FileActions() { posix_spawn_file_actions_init(&actions); }
    ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
};

SpawnError spawn_error(SpawnErrc code, const ChildSpec& spec, std::string what) {
    return SpawnError{code, spec.name, std::move(what)};
}

}  // namespace

Result<ChildProcess, SpawnError> ChildProcess::spawn(const ChildSpec& spec) {
    if (spec.argv.empty() || ::access(spec.argv[0].c_str(), X_OK) != 0) {
        const std::string path = spec.argv.empty() ? std::string("(no program)") : spec.argv[0];
        return Err{spawn_error(SpawnErrc::kNotExecutable, spec,
                               path + ": " + std::strerror(errno) + " (build it first?)")};
    }
    FileActions files;
    int log_fd = -1;
    if (!spec.log_file.empty()) {
        log_fd = ::open(spec.log_file.c_str(),
                        O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0640);
        if (log_fd < 0) {
            return Err{spawn_error(SpawnErrc::kLogFile, spec,
                                   spec.log_file.string() + ": " + std::strerror(errno))};
        }
        posix_spawn_file_actions_adddup2(&files.actions, log_fd, STDOUT_FILENO);
        posix_spawn_file_actions_adddup2(&files.actions, log_fd, STDERR_FILENO);
    }
    std::vector<char*> argv, envp;
    for (const auto& a : spec.argv) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    for (char** e = environ; *e; ++e) envp.push_back(*e);
    for (const auto& e : spec.extra_env) envp.push_back(const_cast<char*>(e.c_str()));
    envp.push_back(nullptr);
    SpawnAttributes attrs;
    pid_t pid = -1;
    const int rc =
        ::posix_spawn(&pid, argv[0], &files.actions, &attrs.attr, argv.data(), envp.data());
    if (log_fd >= 0) ::close(log_fd);  // the child has its own copy
    if (rc != 0) return Err{spawn_error(SpawnErrc::kSpawnFailed, spec, std::strerror(rc))};
    return ChildProcess(spec.name, pid);
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : name_(std::move(other.name_)), pid_(other.pid_), exit_(other.exit_) {
    other.pid_ = -1;
}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
    if (this != &other) {
        if (running()) stop(std::chrono::seconds(2));
        name_ = std::move(other.name_);
        pid_ = other.pid_;
        exit_ = other.exit_;
        other.pid_ = -1;
    }
    return *this;
}

ChildProcess::~ChildProcess() {
    if (running()) stop(std::chrono::seconds(2));
}

const std::optional<ExitInfo>& ChildProcess::poll() {
    if (!running()) return exit_;
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == pid_) exit_ = ExitInfo{status};
    if (r < 0 && errno == ECHILD) exit_ = ExitInfo{0};  // reaped elsewhere: treat as gone
    return exit_;
}

const std::optional<ExitInfo>& ChildProcess::wait_for(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!poll().has_value() && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return exit_;
}

void ChildProcess::signal(int sig) noexcept {
    if (running()) ::kill(pid_, sig);
}

ExitInfo ChildProcess::stop(std::chrono::milliseconds grace) {
    if (!running()) return exit_.value_or(ExitInfo{});
    signal(SIGCONT);  // a stopped child cannot act on SIGTERM
    signal(SIGTERM);
    if (!wait_for(grace).has_value()) {
        signal(SIGKILL);
        while (!wait_for(std::chrono::seconds(1)).has_value()) signal(SIGKILL);
    }
    return *exit_;
}

std::filesystem::path executable_dir() {
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::filesystem::current_path() : self.parent_path();
}

}  // namespace kerf::supervise
