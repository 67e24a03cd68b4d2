#include "rt_core/loop/lockstep_world_sync.hpp"

#include <chrono>
#include <thread>

#include "rt_core/loop/haptic_loop.hpp"

namespace kerf::rt {

firmware_host::DeviceStatus LockstepWorldSync::try_read(firmware_host::DeviceSample& out,
                                                        std::uint32_t timeout_us) noexcept {
    if (loop_ && release_ && offered_) {
        // last_physics() is the previous tick's (this read comes before this tick's physics).
        const physics::SawOutput& saw = loop_->last_physics().saw;
        bool cut_ended = false;
        for (std::uint32_t i = 0; i < saw.event_count; ++i)
            cut_ended = cut_ended || saw.events[i].type == physics::CutEventType::kEnd;
        if (cut_ended) {
            const std::uint64_t due = loop_->world_generation() + 1;
            release_->store(due, std::memory_order_release);
            const auto limit =
                std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_limit_ms_);
            while (offered_->load(std::memory_order_acquire) < due &&
                   std::chrono::steady_clock::now() < limit)
                std::this_thread::sleep_for(std::chrono::microseconds(200));
            ++(offered_->load(std::memory_order_acquire) >= due ? synced_ : timed_out_);
        }
    }
    return inner_.try_read(out, timeout_us);
}

}  // namespace kerf::rt
