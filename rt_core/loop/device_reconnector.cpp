#include "rt_core/loop/device_reconnector.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

namespace kerf::rt {
namespace {

bool power_of_two(std::uint64_t n) { return n != 0 && (n & (n - 1)) == 0; }

}  // namespace

DeviceReconnector::DeviceReconnector(const DeviceLink& link, Handoff<DeviceSlot>& handoff,
                                     Opener opener, const ReopenBackoff& backoff)
    : link_(link), handoff_(handoff), opener_(std::move(opener)), backoff_(backoff) {}

DeviceReconnector::~DeviceReconnector() { stop(); }

void DeviceReconnector::start() {
    if (thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        stop_ = false;
    }
    thread_ = std::thread([this] { run(); });
}

void DeviceReconnector::stop() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    handoff_.collect();
}

ReconnectStats DeviceReconnector::stats() const noexcept {
    return {attempts_.load(std::memory_order_relaxed), reopened_.load(std::memory_order_relaxed),
            failures_.load(std::memory_order_relaxed)};
}

std::string DeviceReconnector::last_error() const {
    std::lock_guard lock(mutex_);
    return last_error_;
}

bool DeviceReconnector::sleep_ms(std::uint32_t ms) {
    std::unique_lock lock(mutex_);
    return !wake_.wait_for(lock, std::chrono::milliseconds(ms), [this] { return stop_; });
}

void DeviceReconnector::run() {
    std::uint32_t backoff_ms = backoff_.first_ms;
    for (;;) {
        handoff_.collect();  // the devices the loop retired: closed and freed here
        // The newest device we know of is lost (not one still on its way to the loop): open again.
        if (link_.lost_generation(reopened_.load(std::memory_order_relaxed))) {
            const bool opened = try_once(backoff_ms);
            if (!sleep_ms(opened ? backoff_.poll_ms : backoff_ms)) return;
            continue;
        }
        backoff_ms = backoff_.first_ms;
        if (!sleep_ms(backoff_.poll_ms)) return;
    }
}

bool DeviceReconnector::try_once(std::uint32_t& backoff_ms) {
    attempts_.fetch_add(1, std::memory_order_relaxed);
    auto opened = opener_();
    if (!opened) {
        backoff_ms = std::min(backoff_ms * 2, backoff_.max_ms);
        const std::uint64_t n = failures_.fetch_add(1, std::memory_order_relaxed) + 1;
        if (power_of_two(n))  // 1st, 2nd, 4th, ... failure: the log stays readable
            spdlog::warn("kerf-rt: device re-open failed ({} so far, next try in {} ms): {}", n,
                         backoff_ms, opened.error());
        {
            std::lock_guard lock(mutex_);
            last_error_ = opened.error();
        }
        return false;
    }
    auto slot = std::make_unique<DeviceSlot>();
    slot->device = std::move(*opened);
    slot->generation = reopened_.fetch_add(1, std::memory_order_relaxed) + 1;
    spdlog::info("kerf-rt: device re-opened (re-open {}), handing it to the loop",
                 slot->generation);
    handoff_.offer(std::move(slot));
    return true;
}

}  // namespace kerf::rt
