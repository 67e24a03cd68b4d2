#include "rt_core/loop/rt_log.hpp"

#include <spdlog/spdlog.h>
#include <time.h>

#include <chrono>

namespace kerf::rt {

std::string_view to_string(LogCode code) noexcept {
    switch (code) {
        case LogCode::kSafeStateEntered:
            return "timing: safe state (zero force) at tick {} after {} missed deadlines in a row";
        case LogCode::kSafeStateLeft:
            return "timing: recovered at tick {} after {} ticks in safe state";
        case LogCode::kDeviceState:
            return "device state {} (was {})";
        case LogCode::kWorldSwapped:
            return "collision world generation {} ({} bodies) swapped in";
        case LogCode::kProfileSwapped:
            return "force profile swapped in: {} values changed (revision {})";
        case LogCode::kOverrun:
            return "overrun at tick {}: work took {} ns";
        case LogCode::kCutEvent:
            return "cut event type {} (cut {})";
        case LogCode::kEventNotJournalled:
            return "event {} could not be journalled ({} so far: journal queue full)";
        case LogCode::kDeviceLost:
            return "device lost at tick {} (loss {}): zero force, re-opening off the loop";
        case LogCode::kDeviceReopened:
            return "re-opened device {} installed at tick {}: engages when quiet, ramping in";
    }
    return "unknown log code {} {}";
}

RtLog::RtLog() : ring_(std::make_unique<Ring>()) {
    producer_ = ipc::SpscProducerEnd<LogRecord, kCapacity>(&ring_->control, ring_->slots);
    consumer_ = ipc::SpscConsumerEnd<LogRecord, kCapacity>(&ring_->control, ring_->slots);
}

bool RtLog::try_push(LogCode code, double a, double b) noexcept {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    LogRecord r{};
    r.time_ns = std::uint64_t(ts.tv_sec) * 1'000'000'000ull + std::uint64_t(ts.tv_nsec);
    r.code = code;
    r.a = a;
    r.b = b;
    return producer_.try_push(r);
}

bool RtLog::try_pop(LogRecord& out) noexcept {
    return consumer_.try_pop(out) == ipc::PopResult::kOk;
}

RtLogDrain::RtLogDrain(RtLog& log, std::uint32_t period_ms) : log_(log) {
    thread_ = std::thread([this, period_ms] {
        while (!stop_.load(std::memory_order_acquire)) {
            drain_once();
            std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
        }
        drain_once();
    });
}

RtLogDrain::~RtLogDrain() {
    stop_.store(true, std::memory_order_release);
    thread_.join();
}

void RtLogDrain::drain_once() {
    LogRecord r;
    while (log_.try_pop(r)) {
        const std::string text = fmt::format(fmt::runtime(to_string(r.code)), r.a, r.b);
        if (r.code == LogCode::kSafeStateEntered || r.code == LogCode::kEventNotJournalled ||
            r.code == LogCode::kDeviceLost) {
            spdlog::warn("kerf-rt: {}", text);
        } else {
            spdlog::info("kerf-rt: {}", text);
        }
    }
}

}  // namespace kerf::rt
