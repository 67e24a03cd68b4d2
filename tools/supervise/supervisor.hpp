// kerf::supervise::Supervisor — starts the simulator's processes in order, watches them, restarts
// the ones allowed to restart (the display), and stops everything in reverse order on a stop
// request (SIGINT / SIGTERM to the supervisor) or when a process the session cannot live without
// (kerf-rt, the emulator) ends. Used by `kerf demo` and `kerf run`.
//
//   Supervisor sup;
//   sup.add({hapsim_spec, Policy::kEssential});
//   sup.add({rt_spec, Policy::kEssential}, [&] { return session_ready(); });   // waits for it
//   sup.add({display_spec, Policy::kRestart});
//   const RunOutcome out = sup.run([&] { return demo_finished(); });
//   sup.stop_all();
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tools/supervise/child_process.hpp"

namespace kerf::supervise {

/// What the supervisor does when a process ends.
enum class Policy : std::uint8_t {
    kEssential,  ///< its end (any status) ends the session
    kRestart,    ///< restarted after a back-off (1 s doubling to 8 s); the session goes on
    kMayFinish,  ///< a zero exit is its job done; a non-zero exit ends the session
};

struct Role {
    ChildSpec spec;
    Policy policy = Policy::kEssential;
};

/// Why run() returned.
struct RunOutcome {
    enum class Reason : std::uint8_t { kDone, kStopSignal, kProcessEnded, kStartFailed } reason;
    std::string detail;  ///< which process and how it ended, or the signal
    bool ok() const noexcept { return reason == Reason::kDone; }
};

class Supervisor {
public:
    /// Installs SIGINT/SIGTERM/SIGHUP handlers that request a stop (restored on destruction).
    Supervisor();
    ~Supervisor();  ///< stop_all()
    Supervisor(const Supervisor&) = delete;
    Supervisor& operator=(const Supervisor&) = delete;

    /// Starts `role` now; then, if `ready` is given, waits until it returns true (polled every
    /// 10 ms) or `ready_timeout` passes, failing if the process ends or a stop is requested.
    Result<ChildProcess*, SpawnError> add(
        Role role, const std::function<bool()>& ready = {},
        std::chrono::milliseconds ready_timeout = std::chrono::seconds(30));

    /// Watches the processes until `done()` returns true, a stop is requested or an essential
    /// process ends. Restarts kRestart processes; `on_restart(name, count)` is told each time.
    RunOutcome run(const std::function<bool()>& done,
                   const std::function<void(const std::string&, int)>& on_restart = {});

    /// Stops every running process in reverse start order (SIGTERM, grace, SIGKILL).
    void stop_all(std::chrono::milliseconds grace = std::chrono::seconds(3));

    /// The process started for `name`, or nullptr.
    ChildProcess* find(const std::string& name) noexcept;
    /// How many times `name` was restarted.
    int restarts(const std::string& name) const noexcept;

    /// True once SIGINT/SIGTERM/SIGHUP arrived (or request_stop() was called).
    static bool stop_requested() noexcept;
    static void request_stop() noexcept;
    /// The signal that requested the stop, 0 if none.
    static int stop_signal() noexcept;

private:
    struct Entry {
        Role role;
        std::optional<ChildProcess> process;
        int restarts = 0;
        std::chrono::steady_clock::time_point restart_at{};
    };
    std::vector<Entry> entries_;
};

}  // namespace kerf::supervise
