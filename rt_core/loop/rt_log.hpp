// kerf::rt::RtLog — logging from the real-time thread without logging on it: the loop pushes
// fixed-size records (a code and two numbers) into an in-process SPSC ring; a non-real-time
// thread drains the ring every few milliseconds and writes the lines with spdlog. A full ring
// drops the record and counts it.
//
//   RT:     log.try_push(LogCode::kSafeStateEntered, tick, misses);   // noexcept, wait-free
//   non-RT: RtLogDrain drain(log);  ...  (its thread prints until destroyed)
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string_view>
#include <thread>

#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::rt {

/// What happened; each code has one fixed message (to_string) the drain formats with a and b.
enum class LogCode : std::uint16_t {
    kSafeStateEntered,    ///< a = tick, b = consecutive misses
    kSafeStateLeft,       ///< a = tick, b = ticks spent in safe state
    kDeviceState,         ///< a = new DeviceState, b = previous
    kWorldSwapped,        ///< a = mesh generation, b = bodies
    kProfileSwapped,      ///< a = changed values, b = 0
    kOverrun,             ///< a = tick, b = compute ns
    kCutEvent,            ///< a = EventType, b = cut id
    kEventNotJournalled,  ///< a = sequence, b = 0
    kDeviceLost,          ///< a = tick, b = losses so far
    kDeviceReopened,      ///< a = re-open generation, b = tick
};
std::string_view to_string(LogCode code) noexcept;

struct LogRecord {
    std::uint64_t time_ns;  ///< CLOCK_MONOTONIC
    LogCode code;
    std::uint16_t reserved[3];
    double a;
    double b;
};

class RtLog {
public:
    static constexpr std::uint32_t kCapacity = 1024;
    RtLog();
    /// RT: queues a record; false (and counted) when the ring is full. noexcept, wait-free.
    bool try_push(LogCode code, double a, double b) noexcept;
    /// Non-RT (one thread): pops the oldest record.
    bool try_pop(LogRecord& out) noexcept;
    std::uint64_t dropped() const noexcept { return producer_.dropped(); }

private:
    struct Ring {
        ipc::RingControl control{};
        LogRecord slots[kCapacity];
    };
    std::unique_ptr<Ring> ring_;
    ipc::SpscProducerEnd<LogRecord, kCapacity> producer_;
    ipc::SpscConsumerEnd<LogRecord, kCapacity> consumer_;
};

/// A thread printing what the loop logged (spdlog, prefix "kerf-rt:"), every `period_ms`.
class RtLogDrain {
public:
    explicit RtLogDrain(RtLog& log, std::uint32_t period_ms = 20);
    ~RtLogDrain();  ///< drains what is left, then joins
    RtLogDrain(const RtLogDrain&) = delete;
    RtLogDrain& operator=(const RtLogDrain&) = delete;

private:
    void drain_once();
    RtLog& log_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace kerf::rt
