// Runs the real kerf-hapsim executable (fork/exec from KERF_BIN_DIR) for integration tests:
// waits for its `ready` line, sends stdin commands and waits for their `ok`, stops it cleanly.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace kerf::firmware_host::test {

class HapsimProcess {
public:
    /// Starts kerf-hapsim with `args` plus --socket <socket_path> --commands (an empty path: a
    /// unique one under /tmp; a given one lets a test restart an emulator where a host expects it).
    explicit HapsimProcess(std::vector<std::string> args, std::string socket_path = {});
    ~HapsimProcess();
    HapsimProcess(const HapsimProcess&) = delete;
    HapsimProcess& operator=(const HapsimProcess&) = delete;

    bool ready() const { return ready_; }
    pid_t pid() const { return pid_; }
    const std::string& socket_path() const { return socket_; }
    /// Sends one command line; true when kerf-hapsim answered `ok`.
    bool command(const std::string& line);
    /// Asks it to quit and waits (kills after a timeout); returns the exit status.
    int stop();
    /// SIGKILLs it (a crashed emulator: its socket file stays) and reaps it.
    void kill();
    /// Everything it wrote on stdout so far (for failure messages).
    const std::string& output() const { return out_; }

private:
    bool read_line(std::string& line, int timeout_ms);
    pid_t pid_ = -1;
    int to_child_ = -1;
    int from_child_ = -1;
    bool ready_ = false;
    std::string socket_;
    std::string out_, pending_;
};

/// A unique path under /tmp for sockets, traces and dummy firmware images.
std::string temp_path(const std::string& stem);

}  // namespace kerf::firmware_host::test
