#include "tools/supervise/supervisor.hpp"

#include <csignal>
#include <cstring>
#include <thread>

namespace kerf::supervise {
namespace {

std::atomic<int> g_stop_signal{0};
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[3];

extern "C" void on_stop_signal(int sig) { g_stop_signal.store(sig, std::memory_order_relaxed); }

constexpr auto kPoll = std::chrono::milliseconds(10);

std::chrono::milliseconds backoff(int restarts) {
    const int shift = restarts < 3 ? restarts : 3;
    return std::chrono::milliseconds(1000 << shift);  // 1, 2, 4, 8 s
}

}  // namespace

Supervisor::Supervisor() {
    g_stop_signal.store(0, std::memory_order_relaxed);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    for (int k = 0; k < 3; ++k) ::sigaction(kStopSignals[k], &sa, &g_previous[k]);
}

Supervisor::~Supervisor() {
    stop_all();
    for (int k = 0; k < 3; ++k) ::sigaction(kStopSignals[k], &g_previous[k], nullptr);
}

bool Supervisor::stop_requested() noexcept {
    return g_stop_signal.load(std::memory_order_relaxed) != 0;
}
void Supervisor::request_stop() noexcept {
    int expected = 0;
    g_stop_signal.compare_exchange_strong(expected, -1);
}
int Supervisor::stop_signal() noexcept {
    const int s = g_stop_signal.load(std::memory_order_relaxed);
    return s > 0 ? s : 0;
}

Result<ChildProcess*, SpawnError> Supervisor::add(Role role, const std::function<bool()>& ready,
                                                  std::chrono::milliseconds ready_timeout) {
    auto child = ChildProcess::spawn(role.spec);
    if (!child) return Err{std::move(child).error()};
    Entry& e = entries_.emplace_back(Entry{std::move(role), std::move(*child), 0, {}});
    ChildProcess& proc = *e.process;
    if (!ready) return &proc;
    const auto deadline = std::chrono::steady_clock::now() + ready_timeout;
    while (!ready()) {
        if (proc.poll().has_value()) {
            return Err{SpawnError{
                SpawnErrc::kSpawnFailed, proc.name(),
                "ended before it was ready (" + proc.exit_info()->describe() + "; see its log)"}};
        }
        if (stop_requested()) {
            return Err{SpawnError{SpawnErrc::kSpawnFailed, proc.name(),
                                  "stop requested while waiting for it to get ready"}};
        }
        if (std::chrono::steady_clock::now() > deadline) {
            return Err{SpawnError{
                SpawnErrc::kSpawnFailed, proc.name(),
                "not ready after " + std::to_string(ready_timeout.count()) + " ms (see its log)"}};
        }
        std::this_thread::sleep_for(kPoll);
    }
    return &proc;
}

RunOutcome Supervisor::run(const std::function<bool()>& done,
                           const std::function<void(const std::string&, int)>& on_restart) {
    using Reason = RunOutcome::Reason;
    for (;;) {
        if (stop_requested()) {
            const int sig = stop_signal();
            return {Reason::kStopSignal,
                    sig > 0 ? std::string("SIG") + sigabbrev_np(sig) : "stop requested"};
        }
        if (done && done()) return {Reason::kDone, {}};
        const auto now = std::chrono::steady_clock::now();
        for (Entry& e : entries_) {
            if (!e.process) continue;
            if (e.process->running()) {
                if (!e.process->poll().has_value()) continue;
                const ExitInfo info = *e.process->exit_info();
                switch (e.role.policy) {
                    case Policy::kEssential:
                        return {Reason::kProcessEnded, e.role.spec.name + " " + info.describe()};
                    case Policy::kMayFinish:
                        if (!info.success()) {
                            return {Reason::kProcessEnded,
                                    e.role.spec.name + " " + info.describe()};
                        }
                        continue;
                    case Policy::kRestart:
                        e.restart_at = now + backoff(e.restarts);
                        continue;
                }
            }
            if (e.role.policy != Policy::kRestart || now < e.restart_at) continue;
            auto again = ChildProcess::spawn(e.role.spec);
            if (!again) return {Reason::kStartFailed, again.error().message()};
            e.process = std::move(*again);
            ++e.restarts;
            if (on_restart) on_restart(e.role.spec.name, e.restarts);
        }
        std::this_thread::sleep_for(kPoll);
    }
}

void Supervisor::stop_all(std::chrono::milliseconds grace) {
    for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {
        if (it->process && it->process->running()) it->process->stop(grace);
    }
}

ChildProcess* Supervisor::find(const std::string& name) noexcept {
    for (Entry& e : entries_) {
        if (e.role.spec.name == name && e.process) return &*e.process;
    }
    return nullptr;
}

int Supervisor::restarts(const std::string& name) const noexcept {
    for (const Entry& e : entries_) {
        if (e.role.spec.name == name) return e.restarts;
    }
    return 0;
}

}  // namespace kerf::supervise
