// kerf::rt::ProfileReloader — the live force profile. A non-real-time thread watches the profile
// file (inotify on its folder: a rename onto it or a close after writing) and reloads on
// request_reload() (kerf-rt calls it on SIGHUP). The config loader parses and validates the new
// file off the real-time thread; a bad file is refused with the loader's file:line:key message and
// the running profile stays. An accepted file becomes a ProfileUpdate (physics and safety
// parameters, one ParameterChange per changed value) handed to the loop, which swaps it in at a
// tick boundary and publishes a ParametersChanged event per change.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include <thread>

#include "config/device_profile.hpp"
#include "config/force_profile.hpp"
#include "rt_core/loop/handoff.hpp"
#include "rt_core/loop/profile_update.hpp"

namespace kerf::rt {

class ProfileReloader {
public:
    /// @pre `handoff` outlives the reloader; `current` is the profile the loop starts with
    ProfileReloader(Handoff<ProfileUpdate>& handoff, std::filesystem::path file,
                    config::ForceProfile current, config::DeviceProfile device, double period_s,
                    physics::PhysicsParams base);
    ~ProfileReloader();  ///< stops the thread
    ProfileReloader(const ProfileReloader&) = delete;
    ProfileReloader& operator=(const ProfileReloader&) = delete;

    /// Starts the watch thread. Returns false (and says why in last_error()) without inotify.
    bool start();
    void stop();
    /// Any thread, async-signal-safe: reload at the watch thread's next poll (<= 50 ms).
    void request_reload() noexcept { requested_.store(true, std::memory_order_release); }
    /// Reloads now on the calling (non-RT) thread; true when a new profile was offered.
    bool reload_now();

    std::uint64_t accepted() const noexcept { return accepted_.load(std::memory_order_acquire); }
    std::uint64_t refused() const noexcept { return refused_.load(std::memory_order_acquire); }
    /// The last refusal, file:line:key (call from the thread that calls reload_now, or after stop).
    const std::string& last_error() const noexcept { return last_error_; }

private:
    void run();
    Handoff<ProfileUpdate>& handoff_;
    std::filesystem::path file_;
    config::ForceProfile committed_;  ///< the profile the loop has (or had before `offered_`)
    config::ForceProfile offered_;    ///< the profile of the last offer
    config::DeviceProfile device_;
    double period_s_;
    physics::PhysicsParams base_;
    int inotify_fd_ = -1;
    std::atomic<bool> requested_{false}, stop_{false};
    std::atomic<std::uint64_t> accepted_{0}, refused_{0};
    std::string last_error_;
    std::thread thread_;
};

}  // namespace kerf::rt
