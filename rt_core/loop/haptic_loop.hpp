// kerf::rt::HapticLoop — one 1 kHz tick of kerf-rt as a short list of named calls:
//
//   swap_at_tick_boundary   new collision world / force profile from their Handoffs
//   read_device             Device::try_read (the one bounded blocking call, lockstep only)
//   compute_kinematics      device frame -> world tool pose (orientation sensed or planned)
//   move_held_body          the grab button's body follows the tool (body_grab.hpp)
//   collide_and_force       kerf_physics ForceModel::step on the collision world
//   apply_safety            ForceSafety (stale, faults, homing, ramp, clamp, slew) + timing
//   write_device            Device::try_write
//   publish                 heartbeat, LatestState, a TelemetrySample, events (rings + journal:
//                           cut events, BodyMoved of a held body)
//
// Every member called from tick() is noexcept and allocates nothing, takes no lock and logs only
// through RtLog. Timing (sleeping to absolute deadlines) is the runner's business
// (loop_runner.hpp); the loop is told how late each tick woke and counts misses: after
// `misses_to_safe_state` in a row it commands zero force, publishes DeviceStateChanged{kSafeStop}
// and leaves the safe state after kRecoveryTicks clean ticks (re-engaging with ramp-in).
#pragma once

#include <cstdint>

#include "config/base/check.hpp"
#include "firmware_host/device/device.hpp"
#include "firmware_host/safety/force_safety.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/loop/blade_pose.hpp"
#include "rt_core/loop/body_grab.hpp"
#include "rt_core/loop/device_front.hpp"
#include "rt_core/loop/device_reconnector.hpp"
#include "rt_core/loop/handoff.hpp"
#include "rt_core/loop/latency_histogram.hpp"
#include "rt_core/loop/profile_update.hpp"
#include "rt_core/loop/rt_log.hpp"
#include "rt_core/loop/world_builder.hpp"
#include "rt_core/physics/collision_world.hpp"
#include "rt_core/physics/force_model.hpp"

namespace kerf::rt {

/// Fixed settings of the loop (configure time).
struct LoopSettings {
    std::int64_t period_ns = 1'000'000;      ///< nominal tick period
    std::uint32_t misses_to_safe_state = 3;  ///< [realtime] consecutive_misses_to_safe_state
    std::uint32_t read_timeout_us = 0;       ///< 0 real time; lockstep: the emulator's answer
    physics::Vec3 device_origin_in_world_m;  ///< world point the device origin maps to
    double motion_scale = 1.0;               ///< world metres per device metre
    BladePlan blade;                         ///< fallback orientation and button steps
    GrabPlan grab;                           ///< the button that holds and moves a body
    bool degraded_realtime = false;          ///< reported in every sample's loop_flags
    bool lockstep = false;  ///< paced by the emulator: tick work includes its answer, no misses
};

/// The loop's always-on invariants (KERF_RT_CHECK codes). A failed check latches: the loop
/// commands zero force with the amplifiers off from that tick on, flags every telemetry sample
/// (kLoopFlagCheckFailed) and kerf-rt names the check in its summary. Never an abort in the loop.
enum class LoopCheck : std::uint16_t {
    kNonFiniteToolPose = 1,  ///< the tool pose (device sample through kinematics) is not finite
    kNonFiniteForce = 2,     ///< the force model returned a non-finite force
};

/// Timing of one tick as the runner measured it.
struct TickTiming {
    std::uint64_t start_ns = 0;          ///< CLOCK_MONOTONIC when the tick's work began
    std::uint64_t wake_latency_ns = 0;   ///< start minus the deadline it slept to
    std::uint64_t missed_deadlines = 0;  ///< deadlines skipped because the tick woke too late
};

/// The timing faults a recorded loop saw at one tick: what a replay re-enacts so that safe-state
/// entries (and so events and forces) happen at the recorded ticks (input_recording.hpp).
struct RecordedTiming {
    std::uint64_t missed_deadlines = 0;  ///< TickTiming::missed_deadlines of the recorded tick
    bool overran_last = false;           ///< the recorded loop's previous tick overran its period
};

/// What a replayed loop takes from its recording besides the device reads (ReplayDevice): each
/// tick's timing faults and the device re-opens. Real-time safe.
class TickReplay {
public:
    virtual ~TickReplay() = default;
    /// Asked once per tick, after the device read: the timing faults of the tick just read.
    virtual RecordedTiming recorded_timing() const noexcept = 0;
    /// Asked at the start of each tick, before the read: the generation of the device the
    /// recorded loop used at this tick (0: the one opened at start; n: its n-th re-open).
    virtual std::uint64_t device_generation_due() const noexcept = 0;
};

/// What the loop saw at one tick, as a recording keeps it (input_recording.hpp).
struct TickSeen {
    std::uint64_t tick = 0;
    std::uint64_t world_generation = 0;   ///< collision world in use (0: the scene)
    std::uint64_t device_generation = 0;  ///< DeviceLink generation of the device in use
    firmware_host::DeviceStatus status = firmware_host::DeviceStatus::kNoData;  ///< of the read;
    ///< kDisconnected on every tick without a device (lost, not yet re-opened: no read)
    const firmware_host::DeviceSample* sample = nullptr;  ///< the loop's sample after the read
    RecordedTiming timing;                                ///< the tick's timing faults
};

/// Takes what the loop saw each tick (InputRecorder: a wait-free ring to a writer thread).
/// Called on the real-time thread: no allocation, no lock, no blocking.
class TickRecorder {
public:
    virtual ~TickRecorder() = default;
    virtual void record(const TickSeen& seen) noexcept = 0;
};

/// Counters since start (read after the loop stopped, or approximately from another thread).
struct LoopStats {
    std::uint64_t ticks = 0;
    std::uint64_t overruns = 0;          ///< ticks whose work exceeded the period
    std::uint64_t missed_deadlines = 0;  ///< deadlines skipped (stalls)
    std::uint64_t late_wakes = 0;        ///< ticks that woke more than one period late
    std::uint64_t safe_state_entries = 0;
    std::uint64_t safe_state_ticks = 0;
    std::uint64_t worlds_swapped = 0;
    std::uint64_t profiles_swapped = 0;
    std::uint64_t events_published = 0;
    std::uint64_t events_not_journalled = 0;
    std::uint64_t device_not_ok = 0;      ///< reads that were not kOk, of which:
    std::uint64_t device_no_data = 0;     ///< ... kNoData: no new sample since the last tick
    std::uint64_t device_malformed = 0;   ///< ... kMalformed: bytes that failed the codec
    std::uint64_t device_error = 0;       ///< ... kError: other transport errors
    std::uint64_t stale_episodes = 0;     ///< times ForceSafety zeroed force for stale samples
    std::uint64_t devices_lost = 0;       ///< reads that found the device disconnected (episodes)
    std::uint64_t devices_reopened = 0;   ///< new devices installed (DeviceReconnector)
    std::uint64_t device_lost_ticks = 0;  ///< ticks run without a device
    LatencyHistogram wake_latency;        ///< ns
    LatencyHistogram compute;             ///< ns, the tick's work
};

class HapticLoop {
public:
    static constexpr std::uint32_t kRecoveryTicks = 100;  ///< clean ticks to leave safe state
    /// m: a re-engaged device's tool this deep in bone gets its proxy on the nearest surface.
    static constexpr double kReengageReach = 0.05;

    /// Configure: everything allocated here. `device`, `producer` and `log` outlive the loop.
    HapticLoop(firmware_host::Device& device, ipc::Producer& producer, RtLog& log,
               const LoopSettings& settings, const physics::PhysicsParams& physics,
               const firmware_host::SafetyLimits& safety);
    ~HapticLoop();  ///< frees the installed world and profile (call after the loop stopped)
    HapticLoop(const HapticLoop&) = delete;
    HapticLoop& operator=(const HapticLoop&) = delete;

    /// The first command: zero force (lockstep emulators answer host packets). noexcept.
    void prime() noexcept;
    /// One tick. noexcept, allocation-free, lock-free, bounded.
    void tick(const TickTiming& timing) noexcept;
    /// Before the loop runs: marks telemetry as coming from a degraded (non-FIFO) loop.
    void set_degraded_realtime(bool degraded) noexcept { settings_.degraded_realtime = degraded; }
    /// After tick(): the time the tick's work took (the runner measures it). noexcept.
    void record_compute(std::uint64_t compute_ns) noexcept;
    /// Commands zero force with the amplifiers off (shutdown, signals). noexcept.
    void command_zero() noexcept;
    /// Before the loop runs (kerf-rt --replay): each tick takes its missed deadlines and the
    /// previous tick's overrun from `source` instead of the runner's clock, so a recording made in
    /// real time, stalls included, replays in lockstep to the same safe-state entries; a device
    /// lost in the recording is still read (the recording says what each tick without a device
    /// saw), and the recorded re-opens are re-enacted at their ticks (the same reset as a new
    /// device: zero force, re-engage, proxy outside the bone) on the same replayed device.
    void replay_from(const TickReplay* source) noexcept { replay_ = source; }
    /// Before the loop runs: every tick, what the loop saw is handed to `recorder` (nullptr:
    /// none). Recorded from inside the loop, so ticks without a device and a re-opened device
    /// are recorded as well.
    void record_to(TickRecorder* recorder) noexcept { recorder_ = recorder; }
    /// This tick's timing faults as the loop counts them (or as replayed).
    RecordedTiming tick_timing() const noexcept { return tick_timing_; }
    /// From the loop thread while a tick is held up on purpose (a replay waiting for its recorded
    /// collision world): refreshes the heartbeat so consumers still see a live producer. noexcept.
    void keep_alive() noexcept;

    Handoff<WorldSnapshot>& world_handoff() noexcept { return world_handoff_; }
    Handoff<ProfileUpdate>& profile_handoff() noexcept { return profile_handoff_; }
    /// Re-opened devices for the loop (DeviceReconnector offers, the loop takes and retires).
    Handoff<DeviceSlot>& device_handoff() noexcept { return device_handoff_; }
    /// Whether the device is lost, and which one is installed (DeviceReconnector reads it).
    const DeviceLink& device_link() const noexcept { return device_link_; }
    /// Before the loop runs: the loop reads and writes through `front`, and a re-opened device
    /// goes behind it (DeviceFront::set_inner) instead of replacing it. @pre `front` outlives
    /// the loop
    void keep_in_front(DeviceFront& front) noexcept { front_ = &front, device_ = &front; }
    /// The device in use (the one given at construction until a re-open replaced it; the front
    /// when there is one). Read it from another thread only while the loop is stopped.
    firmware_host::Device& device() noexcept { return *device_; }
    /// True from the tick a read found the device gone until a new one is installed.
    bool waiting_for_device() const noexcept { return device_lost_; }
    const LoopStats& stats() const noexcept { return stats_; }
    /// The force commanded by the last tick, device frame, N.
    const firmware_host::Vec3& last_force_n() const noexcept { return command_.force_n; }
    const physics::PhysicsOutput& last_physics() const noexcept { return physics_out_; }
    /// The blade's orientation source and pose this tick.
    const BladePose& blade() const noexcept { return blade_; }
    /// The body the hand holds, if any.
    const BodyGrab& grab() const noexcept { return grab_; }
    /// The tool position of the last tick, world frame, m.
    const physics::Vec3& tool_position_m() const noexcept { return tool_.pose.position_m; }
    bool in_safe_state() const noexcept { return safe_state_; }
    /// The safety layer (engaged, reasons of the last tick).
    const firmware_host::ForceSafety& safety() const noexcept { return safety_; }
    /// The latched failed invariant, if any (readable from any thread; see LoopCheck).
    const FaultLatch& checks() const noexcept { return checks_; }
    /// This tick's device read result and the newest sample (tests, tools).
    firmware_host::DeviceStatus last_read_status() const noexcept { return read_status_; }
    const firmware_host::DeviceSample& last_sample() const noexcept { return sample_; }
    ipc::DeviceState device_state() const noexcept { return device_state_; }
    std::uint64_t world_generation() const noexcept { return world_ ? world_->generation : 0; }

private:
    void swap_at_tick_boundary() noexcept;
    void read_device() noexcept;
    void compute_kinematics() noexcept;
    void move_held_body() noexcept;
    void collide_and_force() noexcept;
    void apply_safety(const TickTiming& timing) noexcept;
    void write_device() noexcept;
    void publish(const TickTiming& timing) noexcept;

    void install_world(WorldSnapshot* world) noexcept;
    void install_profile(ProfileUpdate* update) noexcept;
    void install_device(DeviceSlot* slot) noexcept;
    void restart_device(std::uint64_t generation) noexcept;
    void record_tick() noexcept;
    void track_timing(const TickTiming& timing) noexcept;
    void track_device_state() noexcept;
    void publish_cut_events() noexcept;
    void publish_body_move() noexcept;
    void publish_device_state(ipc::DeviceState next) noexcept;
    void publish_event(ipc::EventRecord& record) noexcept;

    firmware_host::Device* device_;
    DeviceFront* front_ = nullptr;  ///< keep_in_front()
    ipc::Producer& producer_;
    RtLog& log_;
    LoopSettings settings_;
    physics::ForceModel model_;
    physics::CollisionWorld collision_;
    firmware_host::ForceSafety safety_;
    BladePose blade_;
    BodyGrab grab_;
    BodyMove body_move_;              ///< this tick's pose of the held body ...
    bool body_move_pending_ = false;  ///< ... to publish as BodyMoved
    Handoff<WorldSnapshot> world_handoff_;
    Handoff<ProfileUpdate> profile_handoff_;
    WorldSnapshot* world_ = nullptr;
    ProfileUpdate* profile_ = nullptr;
    Handoff<DeviceSlot> device_handoff_;
    DeviceSlot* device_slot_ = nullptr;  ///< the re-opened device in use (nullptr: the first)
    DeviceLink device_link_;
    bool device_lost_ = false;

    firmware_host::DeviceSample sample_;
    firmware_host::DeviceStatus read_status_ = firmware_host::DeviceStatus::kNoData;
    firmware_host::DeviceCommand command_;
    physics::ToolInput tool_;
    physics::PhysicsOutput physics_out_;
    bool proxy_reset_ = false;
    bool proxy_outside_ = false;
    bool stale_last_ = false;  ///< ForceSafety reported stale samples last tick  ///< the next
                               ///< proxy reset places it outside the bone
    std::uint64_t last_sample_count_ = 0;

    std::uint64_t tick_ = 0;
    std::uint64_t last_start_ns_ = 0;
    std::uint32_t consecutive_misses_ = 0;
    std::uint32_t clean_ticks_ = 0;
    std::uint32_t consecutive_not_ok_ = 0;
    bool safe_state_ = false;
    FaultLatch checks_;
    bool overran_last_ = false;
    RecordedTiming tick_timing_;          ///< this tick's, set before the device read
    const TickReplay* replay_ = nullptr;  ///< replay: recorded timing and re-opens instead
    TickRecorder* recorder_ = nullptr;    ///< record: what the loop saw, every tick
    ipc::DeviceState device_state_ = ipc::DeviceState::kConnecting;
    std::uint32_t period_ns_max_ = 0, compute_ns_max_ = 0;
    LoopStats stats_;
};

}  // namespace kerf::rt
