// kerf::supervise::ChildProcess — one child program the `kerf` front door starts and owns
// (kerf-hapsim, kerf-rt, kerf-display). Started with posix_spawn in its own process group, so a
// Ctrl-C in the terminal reaches the supervisor first and the children are stopped in order;
// stdout/stderr go to a log file or are inherited. The destructor stops a child that is still
// running (SIGTERM, then SIGKILL after a grace period) and reaps it: no zombie, no orphan.
//
//   auto rt = ChildProcess::spawn({"kerf-rt", {bin / "kerf-rt", "--config", cfg}, log_dir});
//   if (!rt) { report(rt.error().message()); return 1; }
//   ...
//   const ExitInfo info = rt->stop(std::chrono::seconds(2));   // SIGTERM, wait, SIGKILL
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"

namespace kerf::supervise {

/// Why a child could not be started.
enum class SpawnErrc : std::uint8_t {
    kNotExecutable,  ///< the program does not exist or is not executable
    kLogFile,        ///< the log file could not be created
    kSpawnFailed,    ///< posix_spawn itself failed
};
std::string_view to_string(SpawnErrc code) noexcept;
/// A spawn failure (kerf::Error): which program (`where`) and what went wrong (`what`).
using SpawnError = Error<SpawnErrc>;

/// What to start.
struct ChildSpec {
    std::string name;                    ///< short name for messages ("kerf-rt")
    std::vector<std::string> argv;       ///< argv[0] is the program's path
    std::filesystem::path log_file;      ///< stdout+stderr appended here; empty: inherited
    std::vector<std::string> extra_env;  ///< "NAME=value" added to the supervisor's environment
};

/// How a child ended.
struct ExitInfo {
    int wait_status = 0;  ///< as from waitpid
    bool exited() const noexcept;
    int exit_code() const noexcept;    ///< valid when exited()
    int term_signal() const noexcept;  ///< valid when !exited()
    bool success() const noexcept { return exited() && exit_code() == 0; }
    /// "exited 0", "exited 3", "killed by SIGKILL".
    std::string describe() const;
};

class ChildProcess {
public:
    /// Starts `spec`. The child gets its own process group and default signal dispositions.
    static Result<ChildProcess, SpawnError> spawn(const ChildSpec& spec);

    ChildProcess(ChildProcess&& other) noexcept;
    ChildProcess& operator=(ChildProcess&& other) noexcept;
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;
    ~ChildProcess();  ///< stop(2 s) if still running

    const std::string& name() const noexcept { return name_; }
    pid_t pid() const noexcept { return pid_; }
    /// True until the child has been reaped.
    bool running() const noexcept { return pid_ > 0 && !exit_.has_value(); }
    /// How it ended, once reaped.
    const std::optional<ExitInfo>& exit_info() const noexcept { return exit_; }

    /// Reaps the child if it has ended; never blocks. Returns exit_info().
    const std::optional<ExitInfo>& poll();
    /// Waits up to `timeout` for the child to end (polling every millisecond or so).
    const std::optional<ExitInfo>& wait_for(std::chrono::milliseconds timeout);
    /// Sends `sig` to the child (not its group) if it is still running.
    void signal(int sig) noexcept;
    /// SIGTERM, waits up to `grace`, then SIGKILL and reaps. Idempotent.
    ExitInfo stop(std::chrono::milliseconds grace);

private:
    ChildProcess(std::string name, pid_t pid) : name_(std::move(name)), pid_(pid) {}
    std::string name_;
    pid_t pid_ = -1;
    std::optional<ExitInfo> exit_;
};

/// The folder holding the running `kerf` executable (for finding its sibling programs).
std::filesystem::path executable_dir();

}  // namespace kerf::supervise
