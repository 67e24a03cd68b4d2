// kerf-rt as a real process for tests: a temporary configuration folder (kerf.toml written by the
// test, the shipped device and scene profiles linked, the force profiles copied so a test may edit
// them), fork/exec of build/bin/kerf-rt with its output captured to a file, signals and waiting.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace kerf::rt::test {

/// A temporary config folder. `realtime_toml` replaces the [realtime] table's body.
struct TempConfig {
    explicit TempConfig(const std::string& scene = "calcaneus",
                        const std::string& realtime_toml = "");
    ~TempConfig();
    std::string dir;
    std::string kerf_toml() const { return dir + "/kerf.toml"; }
    std::string force_toml() const { return dir + "/force/default.toml"; }
};

class RtProcess {
public:
    /// Starts kerf-rt with `args` (stdout+stderr into a temp file).
    explicit RtProcess(const std::vector<std::string>& args);
    ~RtProcess();  ///< SIGKILLs it if still running
    pid_t pid() const { return pid_; }
    void signal(int sig) const;
    /// Waits up to `timeout_ms`; the exit status (WEXITSTATUS), or -1 on timeout / signal.
    int wait(int timeout_ms);
    /// Everything it printed so far.
    std::string output() const;
    /// Waits until the output contains `text` (true) or `timeout_ms` passes (false).
    bool wait_for_output(const std::string& text, int timeout_ms) const;

private:
    pid_t pid_ = -1;
    std::string log_;
};

/// A unique session name for one test run.
std::string unique_session(const std::string& stem);

}  // namespace kerf::rt::test
