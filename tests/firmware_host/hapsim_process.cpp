#include "tests/firmware_host/hapsim_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>

namespace kerf::firmware_host::test {

namespace {

std::vector<std::string>& created_paths() {
    static std::vector<std::string> paths;
    return paths;
}

void remove_created_paths() {
    for (const auto& p : created_paths()) ::unlink(p.c_str());
}

}  // namespace

std::string temp_path(const std::string& stem) {
    static std::atomic<int> counter{0};
    static const bool registered = (created_paths(), std::atexit(remove_created_paths) == 0);
    (void)registered;
    std::string path = "/tmp/kerf-test-" + std::to_string(::getpid()) + "-" +
                       std::to_string(counter++) + "-" + stem;
    created_paths().push_back(path);  // removed when the test binary exits
    return path;
}

HapsimProcess::HapsimProcess(std::vector<std::string> args, std::string socket_path)
    : socket_(socket_path.empty() ? temp_path("hapsim.sock") : std::move(socket_path)) {
    args.insert(args.begin(),
                {std::string(KERF_BIN_DIR) + "/kerf-hapsim", "--socket", socket_, "--commands"});
    int in_pipe[2], out_pipe[2];
    if (::pipe2(in_pipe, O_CLOEXEC) != 0 || ::pipe2(out_pipe, O_CLOEXEC) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
        ::dup2(in_pipe[0], STDIN_FILENO);
        ::dup2(out_pipe[1], STDOUT_FILENO);
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(in_pipe[0]);
    ::close(out_pipe[1]);
    to_child_ = in_pipe[1];
    from_child_ = out_pipe[0];
    std::string line;
    while (read_line(line, 5000)) {
        if (line.rfind("ready ", 0) == 0) {
            ready_ = true;
            break;
        }
    }
}

bool HapsimProcess::read_line(std::string& line, int timeout_ms) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
        if (auto nl = pending_.find('\n'); nl != std::string::npos) {
            line = pending_.substr(0, nl);
            pending_.erase(0, nl + 1);
            out_ += line + "\n";
            return true;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                              deadline - std::chrono::steady_clock::now())
                              .count();
        if (left <= 0 || from_child_ < 0) return false;
        pollfd p{from_child_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left)) <= 0) return false;
        char buf[256];
        const auto n = ::read(from_child_, buf, sizeof buf);
        if (n <= 0) return false;
        pending_.append(buf, static_cast<std::size_t>(n));
    }
}

bool HapsimProcess::command(const std::string& line) {
    const std::string l = line + "\n";
    if (::write(to_child_, l.data(), l.size()) != static_cast<ssize_t>(l.size())) return false;
    std::string reply;
    while (read_line(reply, 5000)) {
        if (reply == "ok " + line) return true;
        if (reply.rfind("error", 0) == 0) return false;
    }
    return false;
}

int HapsimProcess::stop() {
    if (pid_ <= 0) return -1;
    if (to_child_ >= 0) {
        (void)::write(to_child_, "quit\n", 5);
        ::close(to_child_);
        to_child_ = -1;
    }
    int status = 0;
    for (int i = 0; i < 300; ++i) {
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        ::usleep(10000);
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return -1;
}

void HapsimProcess::kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    if (to_child_ >= 0) ::close(to_child_);
    to_child_ = -1;
}

HapsimProcess::~HapsimProcess() {
    stop();
    if (from_child_ >= 0) ::close(from_child_);
    ::unlink(socket_.c_str());
}

}  // namespace kerf::firmware_host::test
