#include "rt_core/loop/lockstep_world_sync.hpp"

#include <chrono>
#include <thread>

#include "rt_core/loop/haptic_loop.hpp"

namespace kerf::rt {

void LockstepWorldSync::wait_for(std::uint64_t generation) noexcept {
    release_->store(generation, std::memory_order_release);
    const auto limit = std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_limit_ms_);
    while (offered_->load(std::memory_order_acquire) < generation &&
           std::chrono::steady_clock::now() < limit &&
           !(stop_ && stop_->load(std::memory_order_acquire))) {
        loop_->keep_alive();
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    ++(offered_->load(std::memory_order_acquire) >= generation ? synced_ : timed_out_);
}

firmware_host::DeviceStatus LockstepWorldSync::try_read(firmware_host::DeviceSample& out,
                                                        std::uint32_t timeout_us) noexcept {
    if (loop_ && release_ && offered_ && await_first_) {
        await_first_ = false;
        wait_for(1);  // the display's first collision world
    }
    if (loop_ && release_ && offered_) {
        // last_physics() is the previous tick's (this read comes before this tick's physics).
        const physics::SawOutput& saw = loop_->last_physics().saw;
        bool cut_ended = false;
        for (std::uint32_t i = 0; i < saw.event_count; ++i)
            cut_ended = cut_ended || saw.events[i].type == physics::CutEventType::kEnd;
        if (cut_ended) wait_for(loop_->world_generation() + 1);
    }
    return inner_->try_read(out, timeout_us);
}

}  // namespace kerf::rt
