// kerf::rt::DeviceReconnector — re-opens the haptic device after it was lost (unplugged, the
// emulator killed or restarted), off the real-time thread. The loop only raises a flag when a read
// reports the device disconnected (DeviceLink::report_lost, wait-free); this normal-priority
// thread sees it, opens the device again with exponential back-off (the whole start-up sequence:
// USB/HID open, identity, configuration, Falcon firmware), and hands the new device to the loop
// through a wait-free Handoff. The loop installs it at a tick boundary (HapticLoop: zero force
// until the new device is homed, quiet and ramped in) and retires the old one, which is closed
// and freed here.
//
//   non-RT  DeviceReconnector r(loop.device_link(), loop.device_handoff(), opener, backoff);
//           r.start();  ...  r.stop();
//   RT      link.report_lost()        (HapticLoop::read_device, on kDisconnected)
//   RT      handoff.try_take()        (HapticLoop::swap_at_tick_boundary)
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "config/base/result.hpp"
#include "firmware_host/device/device.hpp"
#include "rt_core/loop/handoff.hpp"

namespace kerf::rt {

/// A re-opened device on its way to the loop (owned by the Handoff until the loop retires it).
struct DeviceSlot {
    std::unique_ptr<firmware_host::Device> device;
    std::uint64_t generation = 0;  ///< 1 for the first re-open, 2 for the next, ...
};

/// The loop's side of the device's health, shared with the reconnector: one word, written only
/// by the loop, (generation of the installed device << 1) | lost. Wait-free both ways.
class DeviceLink {
public:
    /// RT: the current device is gone (idempotent until the next install). noexcept.
    void report_lost() noexcept {
        word_.store(word_.load(std::memory_order_relaxed) | 1u, std::memory_order_release);
    }
    /// RT: the device of re-open `generation` was installed (0: the one opened at start).
    void report_installed(std::uint64_t generation) noexcept {
        word_.store(generation << 1, std::memory_order_release);
    }
    /// Any thread: whether the loop is waiting for a new device.
    bool lost() const noexcept { return (word_.load(std::memory_order_acquire) & 1u) != 0; }
    /// Any thread: the generation of the device the loop uses (or lost).
    std::uint64_t installed_generation() const noexcept {
        return word_.load(std::memory_order_acquire) >> 1;
    }
    /// Any thread: lost, and the lost device is re-open `generation` (the newest one offered).
    bool lost_generation(std::uint64_t generation) const noexcept {
        return word_.load(std::memory_order_acquire) == ((generation << 1) | 1u);
    }

private:
    std::atomic<std::uint64_t> word_{0};
};

/// Back-off between attempts to re-open: first_ms, doubled after each failure, at most max_ms.
struct ReopenBackoff {
    std::uint32_t first_ms = 20;
    std::uint32_t max_ms = 1000;
    std::uint32_t poll_ms = 5;  ///< how often the thread looks at DeviceLink while all is well
};

/// What the reconnector has done (read from any thread).
struct ReconnectStats {
    std::uint64_t attempts = 0;  ///< opens tried
    std::uint64_t reopened = 0;  ///< devices handed to the loop
    std::uint64_t failures = 0;  ///< opens that failed
};

class DeviceReconnector {
public:
    /// Opens the device as at start (allocates, blocks within its own timeouts); error text.
    using Opener = std::function<Result<std::unique_ptr<firmware_host::Device>, std::string>()>;

    /// @pre `link` and `handoff` outlive the reconnector
    DeviceReconnector(const DeviceLink& link, Handoff<DeviceSlot>& handoff, Opener opener,
                      const ReopenBackoff& backoff = {});
    ~DeviceReconnector();  ///< stops the thread
    DeviceReconnector(const DeviceReconnector&) = delete;
    DeviceReconnector& operator=(const DeviceReconnector&) = delete;

    /// Starts the thread (SCHED_OTHER: it inherits the caller's policy, never the loop's).
    void start();
    /// Stops and joins the thread; an attempt in progress finishes first (idempotent).
    void stop();
    ReconnectStats stats() const noexcept;
    /// The last failed attempt's error (empty if none).
    std::string last_error() const;

private:
    void run();
    bool sleep_ms(std::uint32_t ms);           ///< false when stopped meanwhile
    bool try_once(std::uint32_t& backoff_ms);  ///< true when a device was handed over

    const DeviceLink& link_;
    Handoff<DeviceSlot>& handoff_;
    Opener opener_;
    ReopenBackoff backoff_;
    std::atomic<std::uint64_t> attempts_{0}, reopened_{0}, failures_{0};
    mutable std::mutex mutex_;  ///< guards last_error_ and stop_ (never taken by the loop)
    std::condition_variable wake_;
    bool stop_ = false;
    std::string last_error_;
    std::thread thread_;
};

}  // namespace kerf::rt
