// kerf::rt::LockstepWorldSync — makes a lockstep run deterministic across the display: after a
// tick whose physics ended a cut, the next device read waits (bounded) until the world builder
// has offered the next collision world — the one kerf-display publishes once it has applied that
// cut — and the builder offers no world before it is asked for (WorldBuilder::gate). So the cut
// mesh is swapped in exactly two ticks after every cut end, however loaded the machine: without
// this, the loop ran on in the pre-cut world for as many ticks as the display took, and under
// load the blade met the old surface again (spurious cut begins, a different mesh hash).
// With `await_first_world`, the first read also waits (bounded) for kerf-display's first world
// (generation 1), so the loop never ticks on kerf-rt's own scene mesh (one body) while a display
// is coming: without it, the display's first world stayed gated until the first cut ended and
// every later world came one cut late (cut 1 applied to the scene's single body, cut 2 to the
// world before cut 1). Lockstep only: the real-time loop never waits for another process.
// It is a DeviceFront: give it to HapticLoop::keep_in_front, so a device re-opened after an
// unplug goes behind it (before, the re-opened device replaced it and world sync stopped).
#pragma once

#include <atomic>
#include <cstdint>

#include "firmware_host/device/device.hpp"
#include "rt_core/loop/device_front.hpp"

namespace kerf::rt {

class HapticLoop;

class LockstepWorldSync final : public DeviceFront {
public:
    /// @pre `inner` outlives its use here (until set_inner() replaces it)
    explicit LockstepWorldSync(firmware_host::Device& inner,
                               std::uint32_t wait_limit_ms = 10'000) noexcept
        : inner_(&inner), wait_limit_ms_(wait_limit_ms) {}
    /// Before the loop runs: the first read waits for the display's first world.
    void await_first_world(bool on) noexcept { await_first_ = on; }
    /// Before the loop runs: the loop followed, the builder's gate (`release`, which this
    /// advances) and its offered generation. All outlive this device.
    /// Waits keep the loop's heartbeat fresh (HapticLoop::keep_alive), so a display that is
    /// attaching sees a live producer.
    void attach(HapticLoop& loop, std::atomic<std::uint64_t>& release,
                const std::atomic<std::uint64_t>& offered) noexcept {
        loop_ = &loop, release_ = &release, offered_ = &offered;
    }

    firmware_host::DeviceStatus try_read(firmware_host::DeviceSample& out,
                                         std::uint32_t timeout_us) noexcept override;
    firmware_host::DeviceStatus try_write(
        const firmware_host::DeviceCommand& command) noexcept override {
        return inner_->try_write(command);
    }
    const firmware_host::DeviceCounters& counters() const noexcept override {
        return inner_->counters();
    }
    void set_inner(firmware_host::Device& inner) noexcept override { inner_ = &inner; }
    firmware_host::Device& inner() noexcept override { return *inner_; }
    /// Before the loop runs: a wait ends at once when `stop` is set (kerf-rt's SIGINT/SIGTERM),
    /// so a stop request never sits out the wait limit. `stop` outlives this device.
    void stop_waiting_when(const std::atomic<bool>& stop) noexcept { stop_ = &stop; }
    /// Waits (the first world, cut ends) that the world ended within the limit / did not.
    std::uint64_t synced() const noexcept { return synced_; }
    std::uint64_t timed_out() const noexcept { return timed_out_; }

private:
    firmware_host::Device* inner_;
    std::uint32_t wait_limit_ms_;
    std::atomic<std::uint64_t>* release_ = nullptr;
    const std::atomic<std::uint64_t>* offered_ = nullptr;
    HapticLoop* loop_ = nullptr;
    const std::atomic<bool>* stop_ = nullptr;
    std::uint64_t synced_ = 0, timed_out_ = 0;
    bool await_first_ = false;

    void wait_for(std::uint64_t generation) noexcept;
};

}  // namespace kerf::rt
