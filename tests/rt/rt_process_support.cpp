#include "tests/rt/rt_process_support.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "tests/firmware_host/hapsim_process.hpp"

namespace fs = std::filesystem;

namespace kerf::rt::test {

TempConfig::TempConfig(const std::string& scene, const std::string& realtime_toml) {
    dir = firmware_host::test::temp_path("rtcfg");
    fs::create_directories(dir + "/force");
    const std::string src = std::string(KERF_SOURCE_DIR) + "/config";
    fs::create_directory_symlink(src + "/devices", dir + "/devices");
    fs::create_directory_symlink(src + "/scenes", dir + "/scenes");
    for (const auto& f : fs::directory_iterator(src + "/force")) {
        fs::copy_file(f.path(), dir + "/force/" + f.path().filename().string());
    }
    const std::string shared = fs::absolute(fs::path(KERF_SHARED_MESHES).parent_path()).string();
    std::ofstream(kerf_toml())
        << "[profiles]\ndevice = \"simulated\"\nforce = \"default\"\nscene = \"" << scene
        << "\"\n[paths]\nshared = \"" << shared << "\"\n[realtime]\n"
        << (realtime_toml.empty() ? "period_ns = 1_000_000\npolicy = \"fifo\"\npriority = 80\n"
                                    "cpu_affinity = []\nmlockall = true\n"
                                  : realtime_toml)
        << "[journal]\ndir = \"" << dir << "/journal\"\n";
}

TempConfig::~TempConfig() {
    std::error_code ec;
    fs::remove_all(dir, ec);
}

RtProcess::RtProcess(const std::vector<std::string>& args) {
    log_ = firmware_host::test::temp_path("kerf-rt") + ".log";
    std::vector<std::string> full = {std::string(KERF_BIN_DIR) + "/kerf-rt"};
    full.insert(full.end(), args.begin(), args.end());
    pid_ = fork();
    if (pid_ == 0) {
        const int fd = open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        dup2(fd, 1);
        dup2(fd, 2);
        std::vector<char*> argv;
        for (auto& a : full) argv.push_back(a.data());
        argv.push_back(nullptr);
        execv(argv[0], argv.data());
        _exit(127);
    }
}

RtProcess::~RtProcess() {
    if (pid_ > 0) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
    }
    std::error_code ec;
    fs::remove(log_, ec);
}

void RtProcess::signal(int sig) const {
    if (pid_ > 0) kill(pid_, sig);
}

int RtProcess::wait(int timeout_ms) {
    for (int waited = 0; waited <= timeout_ms; waited += 10) {
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
}

std::string RtProcess::output() const {
    std::ifstream f(log_);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

bool RtProcess::wait_for_output(const std::string& text, int timeout_ms) const {
    for (int waited = 0; waited <= timeout_ms; waited += 10) {
        if (output().find(text) != std::string::npos) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

std::string unique_session(const std::string& stem) {
    static int n = 0;
    return "kerf.rt-" + stem + "-" + std::to_string(getpid()) + "-" + std::to_string(n++);
}

}  // namespace kerf::rt::test
