// Record and replay of what kerf-rt's loop read each tick — so a session can be re-run bit for
// bit (`kerf run --record`, `kerf demo`, `kerf replay`).
//
//   record:  the loop hands what it saw each tick (HapticLoop::record_to: the read's status and
//            the sample after it, the collision world and the device generation in use, the
//            tick's timing faults) to InputRecorder on the real-time thread, which pushes one
//            fixed-size RecordedInput into an in-process SPSC ring (wait-free, no allocation; in
//            real time a full ring drops and counts, in lockstep, where the emulator paces the
//            loop, it waits for the drain: WhenFull); InputRecorder's thread drains the ring to
//            FILE.tmp every few milliseconds and renames it to FILE at stop() (a recording that
//            dropped ticks is not kept, and one whose header counts drops is refused: it could not
//            be replayed). Recorded from inside the loop, every tick is there: the ticks without a
//            device (unplugged, not yet re-opened: status kDisconnected) and those of every
//            re-opened device (format 3; format 2 recorded through a wrapper of the device opened
//            at start, so it stopped at an unplug).
//   replay:  ReplayDevice hands the loop the recorded reads tick by tick (status and sample), so
//            kerf-rt --replay FILE runs the same ticks on the same input. The collision world the
//            recorded loop used at each tick is part of the record: the replay device holds the
//            loop (bounded) until the world builder has offered that generation, and the builder
//            offers none before it is due (WorldBuilder's gate), so worlds swap at the recorded
//            ticks. The timing faults the recorded loop saw (missed deadlines, an overrun) and the
//            device re-opens are part of the record too: the replayed loop takes them instead of
//            its own clock's and reconnector's (HapticLoop::replay_from), so a session recorded in
//            real time — stalls, safe-state entries, an unplugged and re-opened device and all —
//            replays to the same events.
//
// File (little-endian x86-64/aarch64, units in the field names): RecordingHeader, then
// RecordedInput records, one per tick from tick 0. Versions read: 1 (no timing), 2 (timing; ends
// where a device was lost), 3 (every tick, device generations, the sample after every read).
// A file with dropped records is refused. The format is described in rt_core/README.md.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "config/base/result.hpp"
#include "firmware_host/device/device.hpp"
#include "rt_core/ipc/spsc_ring.hpp"
#include "rt_core/loop/haptic_loop.hpp"

namespace kerf::rt {

inline constexpr char kRecordingMagic[8] = {'K', 'E', 'R', 'F', 'R', 'E', 'C', '1'};
/// 3: recorded from inside the loop, every tick (device generations; the sample after every
/// read). 2: records carry the tick's timing faults. Version 1 files replay as if the recorded
/// loop never missed a deadline (right for lockstep recordings, which never do). 1 and 2 are read.
inline constexpr std::uint32_t kRecordingVersion = 3;

/// What the loop read from the device in one tick, and the collision world it used. Version 3:
/// the sample is the loop's after the read, whatever its status (a replay restores it); 1 and 2:
/// the sample of a kOk read only.
struct RecordedInput {
    std::uint64_t tick;               ///< 0-based tick of the recorded run
    std::uint64_t world_generation;   ///< collision world in use this tick (0: the scene)
    std::uint64_t sample_count;       ///< DeviceSample::count
    std::uint32_t device_sequence;    ///< DeviceSample::device_sequence
    std::uint32_t buttons;            ///< DeviceSample::buttons
    double position_m[3];             ///< device frame, m
    double velocity_m_per_s[3];       ///< device frame, m/s
    double orientation_wxyz[4];       ///< device frame, unit quaternion
    std::uint32_t command_lag;        ///< DeviceSample::command_lag
    std::uint8_t status;              ///< firmware_host::DeviceStatus of the read
    std::uint8_t flags;               ///< DeviceFlags bits: homed 1, amps 2, estop 4, watchdog 8,
                                      ///< encoder 16, over-temperature 32
    std::uint8_t has_orientation;     ///< 0 or 1
    std::uint8_t overran_last;        ///< 0 or 1: the loop's previous tick overran its period
    std::uint32_t missed_deadlines;   ///< deadlines this tick's wake-up skipped (stalls)
    std::uint32_t device_generation;  ///< version 3: device in use (0 opened at start, n: the
                                      ///< n-th re-open; +1 at most per tick); 1 and 2: 0
};
static_assert(sizeof(RecordedInput) == 128);

/// First bytes of a recording file.
struct RecordingHeader {
    char magic[8];              ///< kRecordingMagic
    std::uint32_t version;      ///< kRecordingVersion
    std::uint32_t record_size;  ///< sizeof(RecordedInput)
    std::uint64_t period_ns;    ///< the recorded loop's period
    std::uint64_t records;      ///< records that follow
    std::uint64_t dropped;      ///< records the ring dropped (a complete recording has 0)
    std::uint64_t reserved[3];  ///< 0
};
static_assert(sizeof(RecordingHeader) == 64);

/// What record() does when the ring is full.
enum class WhenFull {
    kDrop,  ///< real time: the tick goes on, the record is dropped (and the recording refused)
    kWait,  ///< lockstep and replay: the loop is paced by the emulator, not the clock, so it
            ///< waits for the drain (sleeping, up to kMaxWaitWhenFull) and nothing is dropped
};

/// Records what the loop saw each tick (HapticLoop::record_to) through a ring drained into a
/// file by a thread of its own.
class InputRecorder final : public TickRecorder {
public:
    static constexpr std::uint32_t kCapacity = 1u << 15;  ///< ticks the ring holds (32 s at 1 kHz)
    /// Longest a WhenFull::kWait record() waits for the drain before it drops (a drain stuck on
    /// a write): 10 s.
    static constexpr std::chrono::milliseconds kMaxWaitWhenFull{10'000};
    /// Creates FILE.tmp (fails naming it) and starts the drain thread.
    static Result<std::unique_ptr<InputRecorder>, std::string> start(
        const std::string& path, std::uint64_t period_ns, WhenFull when_full = WhenFull::kDrop);
    ~InputRecorder() override;  ///< stop() if not yet stopped
    InputRecorder(const InputRecorder&) = delete;
    InputRecorder& operator=(const InputRecorder&) = delete;

    /// RT: queues one tick's input; false (and counted) when the ring is full. noexcept.
    bool try_push(const RecordedInput& input) noexcept { return producer_.try_push(input); }
    /// What the loop saw this tick, as a RecordedInput: try_push (RT, WhenFull::kDrop), or
    /// push_waiting (WhenFull::kWait; sleeps while the ring is full, so never in real time).
    void record(const TickSeen& seen) noexcept override;
    /// Pushes, sleeping 1 ms at a time while the ring is full, up to kMaxWaitWhenFull; then
    /// try_push (dropped and counted when still full). noexcept.
    bool push_waiting(const RecordedInput& input) noexcept;
    /// Drains what is left, writes the header and renames FILE.tmp to FILE. Idempotent.
    Result<std::uint64_t, std::string> stop();
    std::uint64_t dropped() const noexcept { return producer_.dropped(); }

private:
    InputRecorder() = default;
    void drain() noexcept;
    struct Ring {
        ipc::RingControl control{};
        RecordedInput slots[kCapacity];
    };
    std::unique_ptr<Ring> ring_;
    ipc::SpscProducerEnd<RecordedInput, kCapacity> producer_;
    ipc::SpscConsumerEnd<RecordedInput, kCapacity> consumer_;
    std::string path_;
    std::FILE* file_ = nullptr;
    RecordingHeader header_{};
    WhenFull when_full_ = WhenFull::kDrop;
    bool write_failed_ = false;
    std::atomic<bool> stop_{false};
    std::thread thread_;
    bool stopped_ = false;
};

/// A whole recording, read and validated (untrusted file: size, header, statuses, finiteness).
struct Recording {
    std::uint32_t version = kRecordingVersion;  ///< of the file
    std::uint64_t period_ns = 0;
    std::vector<RecordedInput> inputs;
};
Result<Recording, std::string> load_recording(const std::string& path);

/// How the replay waits for the recorded collision worlds (see WorldBuilder::gate).
struct ReplayWorldGate {
    std::atomic<std::uint64_t>* release = nullptr;        ///< the builder may offer up to this
    const std::atomic<std::uint64_t>* offered = nullptr;  ///< the newest generation offered
    std::uint32_t wait_limit_ms = 30'000;                 ///< then go on and count a late world
    const std::atomic<bool>* stop = nullptr;  ///< set: stop waiting at once (kerf-rt stopping)
    /// Called while waiting (from the loop thread): keeps the session's heartbeat fresh, so a
    /// display can still attach and publish the world the replay waits for. Real-time safe.
    void (*keep_alive)(void* context) noexcept = nullptr;
    void* keep_alive_context = nullptr;
};

/// A Device replaying a recording: try_read returns tick N's recorded status and sample,
/// recorded_timing() that tick's timing faults and device_generation_due() the device generation
/// of the tick to be read next (give it to HapticLoop::replay_from).
class ReplayDevice final : public firmware_host::Device, public TickReplay {
public:
    /// @pre `recording` outlives the device
    ReplayDevice(const Recording& recording, ReplayWorldGate gate) noexcept;
    /// Sets the world gate (before the loop runs).
    void set_gate(ReplayWorldGate gate) noexcept { gate_ = gate; }

    firmware_host::DeviceStatus try_read(firmware_host::DeviceSample& out,
                                         std::uint32_t timeout_us) noexcept override;
    /// Commands go nowhere (the recorded device is not here).
    firmware_host::DeviceStatus try_write(const firmware_host::DeviceCommand&) noexcept override {
        return firmware_host::DeviceStatus::kOk;
    }
    const firmware_host::DeviceCounters& counters() const noexcept override { return counters_; }

    /// The timing faults of the tick try_read last replayed (none before the first).
    RecordedTiming recorded_timing() const noexcept override;
    /// The device generation of the tick try_read replays next (past the end: the last one).
    std::uint64_t device_generation_due() const noexcept override;

    /// Ticks replayed so far.
    std::uint64_t ticks() const noexcept { return next_; }
    /// Worlds that were not offered within the wait limit (the replay may diverge from there).
    std::uint64_t late_worlds() const noexcept { return late_worlds_; }

private:
    const Recording& recording_;
    ReplayWorldGate gate_;
    firmware_host::DeviceCounters counters_;
    std::uint64_t next_ = 0;
    std::uint64_t late_worlds_ = 0;
    std::uint64_t given_up_generation_ = 0;  ///< a world that came too late is not waited for again
};

}  // namespace kerf::rt
