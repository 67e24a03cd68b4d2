// kerf::ipc::Producer — kerf-rt's side of the session segment. Built once by ProducerBuilder
// (creates the segment and the journal, allocates everything); afterwards every per-tick call is
// noexcept, wait-free, allocation-free and never touches a file: real-time safe. A consumer that
// dies, stalls or scribbles over the segment cannot make these calls block, fail or crash.
//
//   auto producer = ProducerBuilder().segment_name("kerf.demo").create();   // configure
//   producer->heartbeat(tick, now_ns);                                        // every tick
//   producer->publish_event(record);  producer->publish_telemetry(sample);   // every tick
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/layout.hpp"

namespace kerf::ipc {

/// What happened to one published event.
struct PublishOutcome {
    std::uint64_t sequence = 0;   ///< the sequence number the event received
    std::uint32_t delivered = 0;  ///< consumer rings it went into
    std::uint32_t dropped = 0;    ///< consumer rings that were full (counted per slot)
    bool journalled = false;      ///< false: journal queue full (counted; a real loss)
};

class Producer {
public:
    Producer(Producer&&) noexcept;
    Producer& operator=(Producer&&) noexcept;
    ~Producer();  ///< stop()s and unlinks the segment (the journal file stays: it is the recording)

    /// Stamps sequence, time (if 0) and checksum into `record`, pushes it into every active
    /// consumer's event ring and into the journal queue. Real-time safe.
    PublishOutcome publish_event(EventRecord& record) noexcept;

    /// Stamps a per-sample sequence and checksum, pushes into every slot that asked for
    /// telemetry; full rings drop and count. Real-time safe.
    void publish_telemetry(TelemetrySample& sample) noexcept;

    /// Publishes the latest state through the seqlock. Wait-free, real-time safe.
    void publish_state(const LatestState& state) noexcept;

    /// Records the loop's liveness: tick number and CLOCK_MONOTONIC ns. Real-time safe.
    void heartbeat(std::uint64_t tick, std::uint64_t now_ns) noexcept;

    /// Non-real-time: flushes the journal, marks the segment stopped. Idempotent.
    void stop();

    /// Non-real-time introspection (tests, tools): the segment this producer writes.
    const SegmentLayout& layout() const noexcept;
    const std::string& segment_name() const noexcept;
    std::string journal_path() const;
    std::string socket_path() const;  ///< the session socket consumers connect to

private:
    struct Impl;
    explicit Producer(std::unique_ptr<Impl> impl) noexcept;
    friend class ProducerBuilder;
    std::unique_ptr<Impl> impl_;
};

class ProducerBuilder {
public:
    ProducerBuilder& segment_name(std::string name);      ///< e.g. "kerf.demo" (from config)
    ProducerBuilder& journal_dir(std::string directory);  ///< default: the session's folder
    ProducerBuilder& group_access(bool enabled);          ///< 0660 instead of 0600
    /// Kiosk group by name ([shm] group; implies group_access; a missing group is an error).
    ProducerBuilder& group(std::string group_name);
    /// Folder of session folders (default default_runtime_dir()).
    ProducerBuilder& runtime_dir(std::string directory);
    ProducerBuilder& journal_flush_period_ns(std::uint64_t period_ns);  ///< default 20 ms

    /// Creates segment + journal, starts the journal thread and the session socket's server
    /// thread (consumers receive the segment and journal descriptors there), marks it running.
    Result<Producer, IpcError> create() const;

private:
    std::string name_;
    std::string journal_dir_;
    std::string runtime_dir_;
    std::string group_name_;
    std::uint64_t flush_period_ns_ = 20'000'000;
    bool group_access_ = false;
};

}  // namespace kerf::ipc
