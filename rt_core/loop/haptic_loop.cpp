#include "rt_core/loop/haptic_loop.hpp"

#include <time.h>

#include <cmath>
#include <cstring>

namespace kerf::rt {
namespace {

using firmware_host::DeviceStatus;

physics::Vec3 to_vec(const firmware_host::Vec3& v) noexcept { return {v[0], v[1], v[2]}; }

/// Quaternion (w, x, y, z) of a rotation matrix (Shepperd's method).
void to_quaternion(const physics::Mat3& r, double (&q)[4]) noexcept {
    const double tr = r.m[0][0] + r.m[1][1] + r.m[2][2];
    if (tr > 0) {
        const double s = std::sqrt(tr + 1.0) * 2;
        q[0] = 0.25 * s, q[1] = (r.m[2][1] - r.m[1][2]) / s;
        q[2] = (r.m[0][2] - r.m[2][0]) / s, q[3] = (r.m[1][0] - r.m[0][1]) / s;
    } else if (r.m[0][0] > r.m[1][1] && r.m[0][0] > r.m[2][2]) {
        const double s = std::sqrt(1.0 + r.m[0][0] - r.m[1][1] - r.m[2][2]) * 2;
        q[0] = (r.m[2][1] - r.m[1][2]) / s, q[1] = 0.25 * s;
        q[2] = (r.m[0][1] + r.m[1][0]) / s, q[3] = (r.m[0][2] + r.m[2][0]) / s;
    } else if (r.m[1][1] > r.m[2][2]) {
        const double s = std::sqrt(1.0 + r.m[1][1] - r.m[0][0] - r.m[2][2]) * 2;
        q[0] = (r.m[0][2] - r.m[2][0]) / s, q[1] = (r.m[0][1] + r.m[1][0]) / s;
        q[2] = 0.25 * s, q[3] = (r.m[1][2] + r.m[2][1]) / s;
    } else {
        const double s = std::sqrt(1.0 + r.m[2][2] - r.m[0][0] - r.m[1][1]) * 2;
        q[0] = (r.m[1][0] - r.m[0][1]) / s, q[1] = (r.m[0][2] + r.m[2][0]) / s;
        q[2] = (r.m[1][2] + r.m[2][1]) / s, q[3] = 0.25 * s;
    }
}

void put(float (&dst)[3], const physics::Vec3& v) noexcept {
    dst[0] = float(v.x), dst[1] = float(v.y), dst[2] = float(v.z);
}

ipc::EventRecord cut_record(const physics::CutEvent& e) noexcept {
    ipc::EventRecord r{};
    r.header.type = e.type == physics::CutEventType::kBegin      ? ipc::EventType::kCutBegin
                    : e.type == physics::CutEventType::kProgress ? ipc::EventType::kCutProgress
                                                                 : ipc::EventType::kCutEnd;
    ipc::CutPayload& c = r.cut;
    c.cut_id = e.cut_id;
    c.body_id = e.body_id;
    put(c.plane_point_m, e.plane_point_m);
    put(c.plane_normal, e.plane_normal);
    put(c.seed_point_m, e.seed_point_m);
    put(c.plane_u, e.plane_u);
    c.triangle_hint = e.triangle_hint;
    c.blade_length_m = float(e.blade.length_m);
    c.blade_depth_m = float(e.blade.depth_m);
    c.kerf_width_m = float(e.blade.kerf_width_m);
    c.swept_u_min_m = float(e.swept.u_min_m);
    c.swept_u_max_m = float(e.swept.u_max_m);
    c.swept_v_min_m = float(e.swept.v_min_m);
    c.swept_v_max_m = float(e.swept.v_max_m);
    c.feed_depth_m = float(e.feed_depth_m);
    c.end_reason = ipc::CutEndReason(std::uint32_t(e.end_reason));
    return r;
}

}  // namespace

HapticLoop::HapticLoop(firmware_host::Device& device, ipc::Producer& producer, RtLog& log,
                       const LoopSettings& settings, const physics::PhysicsParams& physics,
                       const firmware_host::SafetyLimits& safety)
    : device_(&device),
      producer_(producer),
      log_(log),
      settings_(settings),
      model_(physics),
      safety_(safety),
      blade_(settings.blade),
      grab_(settings.grab) {}

HapticLoop::~HapticLoop() {
    delete world_;
    delete profile_;
    delete device_slot_;
}

void HapticLoop::prime() noexcept {
    command_ = firmware_host::DeviceCommand{};
    device_->try_write(command_);
}

void HapticLoop::command_zero() noexcept {
    command_ = firmware_host::DeviceCommand{};
    device_->try_write(command_);
}

void HapticLoop::tick(const TickTiming& measured) noexcept {
    swap_at_tick_boundary();
    if (replay_) {  // a device re-opened at this tick in the recorded run
        const std::uint64_t due = replay_->device_generation_due();
        if (due > device_link_.installed_generation()) restart_device(due);
    }
    tick_timing_ = {measured.missed_deadlines, overran_last_};
    read_device();
    TickTiming timing = measured;
    if (replay_) {
        tick_timing_ = replay_->recorded_timing();
        timing.missed_deadlines = tick_timing_.missed_deadlines;
        overran_last_ = tick_timing_.overran_last;
    }
    if (recorder_) record_tick();
    compute_kinematics();
    move_held_body();
    collide_and_force();
    apply_safety(timing);
    write_device();
    publish(timing);
    ++tick_;
}

void HapticLoop::record_compute(std::uint64_t compute_ns) noexcept {
    stats_.compute.record(compute_ns);
    overran_last_ = !settings_.lockstep && compute_ns > std::uint64_t(settings_.period_ns);
    if (overran_last_) {
        ++stats_.overruns;
        log_.try_push(LogCode::kOverrun, double(tick_), double(compute_ns));
    }
    const auto c = std::uint32_t(compute_ns > 0xFFFFFFFFu ? 0xFFFFFFFFu : compute_ns);
    if (c > compute_ns_max_) compute_ns_max_ = c;
    if (tick_ % 1000 == 0) period_ns_max_ = compute_ns_max_ = 0;  // "in the last second"
}

void HapticLoop::swap_at_tick_boundary() noexcept {
    if (WorldSnapshot* next = world_handoff_.try_take()) install_world(next);
    if (ProfileUpdate* next = profile_handoff_.try_take()) install_profile(next);
    if (DeviceSlot* next = device_handoff_.try_take()) install_device(next);
}

void HapticLoop::record_tick() noexcept {
    TickSeen seen;
    seen.tick = tick_;
    seen.world_generation = world_generation();
    seen.device_generation = device_link_.installed_generation();
    seen.status = read_status_;
    seen.sample = &sample_;
    seen.timing = tick_timing_;
    recorder_->record(seen);
}

void HapticLoop::install_device(DeviceSlot* slot) noexcept {
    device_handoff_.retire(device_slot_);  // closed and freed by the reconnector's thread
    device_slot_ = slot;
    if (front_) {
        front_->set_inner(*slot->device);
    } else {
        device_ = slot->device.get();
    }
    restart_device(slot->generation);
}

void HapticLoop::restart_device(std::uint64_t generation) noexcept {
    device_lost_ = false;
    device_link_.report_installed(generation);
    // A new device starts from nothing: no sample, zero force, engaged again by the safety layer
    // only once homed and quiet, ramping in; the proxy restarts outside the bone.
    sample_ = firmware_host::DeviceSample{};
    read_status_ = DeviceStatus::kNoData;
    last_sample_count_ = 0;
    consecutive_not_ok_ = 0;
    proxy_reset_ = false;
    proxy_outside_ = true;
    safety_ = firmware_host::ForceSafety(safety_.limits());
    command_ = firmware_host::DeviceCommand{};
    device_->try_write(command_);  // lockstep emulators answer host packets
    ++stats_.devices_reopened;
    log_.try_push(LogCode::kDeviceReopened, double(generation), double(tick_));
}

void HapticLoop::install_world(WorldSnapshot* world) noexcept {
    for (std::uint32_t b = 0; b < physics::kMaxBodies; ++b) {
        collision_.set_body(b, b < world->body_count ? world->bodies[b].get() : nullptr);
        if (b < world->body_count) collision_.set_pose(b, world->poses[b]);
    }
    grab_.reapply(collision_);
    world_handoff_.retire(world_);
    world_ = world;
    ++stats_.worlds_swapped;
    log_.try_push(LogCode::kWorldSwapped, double(world->generation), double(world->body_count));
}

void HapticLoop::install_profile(ProfileUpdate* update) noexcept {
    model_.set_params(update->physics);
    safety_.set_limits(update->safety);
    for (std::uint32_t i = 0; i < update->change_count; ++i) {
        const ParameterChange& change = update->changes[i];
        ipc::EventRecord r{};
        r.header.type = ipc::EventType::kParametersChanged;
        r.parameters.parameter_id = change.id;
        r.parameters.value = change.value;
        r.parameters.previous_value = change.previous;
        std::strncpy(r.parameters.name, kForceParameters[change.id].name,
                     sizeof r.parameters.name - 1);
        publish_event(r);
    }
    profile_handoff_.retire(profile_);
    profile_ = update;
    ++stats_.profiles_swapped;
    log_.try_push(LogCode::kProfileSwapped, double(update->change_count), double(update->revision));
}

void HapticLoop::read_device() noexcept {
    // A lost device is not read again (its transport is dead); the reconnector brings a new one.
    // A replay reads every tick: its recording says what each tick without a device saw.
    read_status_ = device_lost_ && !replay_ ? DeviceStatus::kDisconnected
                                            : device_->try_read(sample_, settings_.read_timeout_us);
    if (read_status_ != DeviceStatus::kOk) ++stats_.device_not_ok;
    stats_.device_no_data += read_status_ == DeviceStatus::kNoData ? 1 : 0;
    stats_.device_malformed += read_status_ == DeviceStatus::kMalformed ? 1 : 0;
    stats_.device_error += read_status_ == DeviceStatus::kError ? 1 : 0;
    if (read_status_ == DeviceStatus::kDisconnected && !device_lost_) {
        device_lost_ = true;  // the reconnector opens a new one off this thread
        device_link_.report_lost();
        ++stats_.devices_lost;
        log_.try_push(LogCode::kDeviceLost, double(tick_), double(stats_.devices_lost));
    }
    if (device_lost_) ++stats_.device_lost_ticks;
}

void HapticLoop::compute_kinematics() noexcept {
    const double q[4] = {sample_.orientation_wxyz[0], sample_.orientation_wxyz[1],
                         sample_.orientation_wxyz[2], sample_.orientation_wxyz[3]};
    blade_.update(sample_.buttons, sample_.has_orientation, q);
    const physics::Mat3& r = settings_.blade.world_from_device;
    tool_.pose.position_m = settings_.device_origin_in_world_m +
                            settings_.motion_scale * (r * to_vec(sample_.position_m));
    tool_.pose.orientation = blade_.orientation();
    tool_.velocity_m_s = settings_.motion_scale * (r * to_vec(sample_.velocity_m_per_s));
    tool_.saw_running = blade_.saw_running() && !device_lost_;  // no device: the saw stopped
    KERF_RT_CHECK(
        physics::is_finite(tool_.pose.position_m) && physics::is_finite(tool_.velocity_m_s),
        checks_, LoopCheck::kNonFiniteToolPose);
}

void HapticLoop::move_held_body() noexcept {
    // No device: its last buttons are stale, so the hand lets go. Never while the saw runs.
    const std::uint32_t buttons = device_lost_ ? 0u : sample_.buttons;
    const bool saw_busy = tool_.saw_running || physics_out_.saw.locked;
    body_move_pending_ =
        grab_.update(buttons, tool_.pose.position_m, saw_busy, collision_, body_move_);
}

void HapticLoop::collide_and_force() noexcept {
    const bool fresh = read_status_ == DeviceStatus::kOk && sample_.count != last_sample_count_;
    last_sample_count_ = sample_.count;
    if (checks_.tripped()) {  // never feed a broken pose to the proxy
        physics_out_ = physics::PhysicsOutput{};
        return;
    }
    if (!proxy_reset_) {
        if (!fresh) {
            physics_out_ = physics::PhysicsOutput{};
            return;
        }
        if (proxy_outside_) {  // a re-engaged device: the tool may be inside the bone
            model_.reset_outside(collision_, tool_.pose.position_m, kReengageReach);
        } else {
            model_.reset(tool_.pose.position_m);  // the proxy starts where the tool first is
        }
        proxy_reset_ = true;
    } else if (fresh && (!safety_.engaged() || safe_state_)) {
        // No force reaches the hand, so nothing held the tool back: the proxy must not stay
        // where the surface stopped it (the hand may have pushed the tool deep into or right
        // through the bone meanwhile). Re-seat it each such tick on the nearest surface when the
        // tool is inside, else at the tool, so force resumes towards the way out.
        model_.reset_outside(collision_, tool_.pose.position_m, kReengageReach);
    }
    physics_out_ = model_.step(collision_, tool_, double(settings_.period_ns) * 1e-9);
}

void HapticLoop::apply_safety(const TickTiming& timing) noexcept {
    track_timing(timing);
    // The physics works in the world frame; the device takes forces in its own frame.
    physics::Vec3 f_world = physics_out_.force_n;
    if (!KERF_RT_CHECK(physics::is_finite(f_world), checks_, LoopCheck::kNonFiniteForce))
        f_world = {};
    const physics::Vec3 f_device =
        physics::transpose_times(settings_.blade.world_from_device, f_world);
    firmware_host::SafetyInput in;
    in.desired_force_n = {f_device.x, f_device.y, f_device.z};
    in.read_status = read_status_;
    in.flags = sample_.flags;
    const firmware_host::Vec3 out = safety_.step(in);
    const bool stale = (safety_.reasons() & firmware_host::kReasonStale) != 0;
    if (stale && !stale_last_ && !device_lost_) ++stats_.stale_episodes;
    stale_last_ = stale;
    const bool zero = safe_state_ || checks_.tripped();
    command_.force_n = zero ? firmware_host::Vec3{} : out;
    command_.enable = !zero && safety_.engaged();
    track_device_state();
}

void HapticLoop::track_timing(const TickTiming& timing) noexcept {
    const bool late = timing.missed_deadlines > 0;
    if (late) {
        ++stats_.late_wakes;
        stats_.missed_deadlines += timing.missed_deadlines;
    }
    if (late || overran_last_) {
        consecutive_misses_ += std::uint32_t(timing.missed_deadlines + (overran_last_ ? 1 : 0));
        clean_ticks_ = 0;
    } else {
        consecutive_misses_ = 0;
        ++clean_ticks_;
    }
    if (!safe_state_ && consecutive_misses_ >= settings_.misses_to_safe_state) {
        safe_state_ = true;
        ++stats_.safe_state_entries;
        log_.try_push(LogCode::kSafeStateEntered, double(tick_), double(consecutive_misses_));
    } else if (safe_state_ && clean_ticks_ >= kRecoveryTicks) {
        safe_state_ = false;
        safety_.interrupt();  // resumes with ramp-in after a few fresh samples
        log_.try_push(LogCode::kSafeStateLeft, double(tick_), double(stats_.safe_state_ticks));
    }
    if (safe_state_) ++stats_.safe_state_ticks;
}

void HapticLoop::track_device_state() noexcept {
    consecutive_not_ok_ = read_status_ == DeviceStatus::kOk ? 0 : consecutive_not_ok_ + 1;
    ipc::DeviceState next = ipc::DeviceState::kConnecting;
    if (safe_state_) {
        next = ipc::DeviceState::kSafeStop;
    } else if (device_lost_) {
        next = ipc::DeviceState::kDisconnected;
    } else if (sample_.flags.any_fault() || consecutive_not_ok_ > 50) {
        next = ipc::DeviceState::kFault;
    } else if (sample_.flags.homed) {
        next = ipc::DeviceState::kReady;
    }
    if (next != device_state_) publish_device_state(next);
}

void HapticLoop::keep_alive() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    producer_.heartbeat(tick_,
                        std::uint64_t(ts.tv_sec) * 1'000'000'000u + std::uint64_t(ts.tv_nsec));
}

void HapticLoop::write_device() noexcept {
    if (!device_lost_) device_->try_write(command_);
}

void HapticLoop::publish(const TickTiming& timing) noexcept {
    publish_cut_events();
    publish_body_move();
    const std::uint64_t period = last_start_ns_ ? timing.start_ns - last_start_ns_ : 0;
    last_start_ns_ = timing.start_ns;
    stats_.wake_latency.record(timing.wake_latency_ns);
    producer_.heartbeat(tick_, timing.start_ns);

    double q[4];
    to_quaternion(tool_.pose.orientation, q);
    ipc::TelemetrySample s{};
    s.header.type = ipc::EventType::kTelemetry;
    s.header.time_ns = timing.start_ns;
    s.tool_position_m[0] = tool_.pose.position_m.x;
    s.tool_position_m[1] = tool_.pose.position_m.y;
    s.tool_position_m[2] = tool_.pose.position_m.z;
    for (int i = 0; i < 4; ++i) s.tool_orientation_wxyz[i] = float(q[i]);
    for (int i = 0; i < 3; ++i) s.force_n[i] = float(command_.force_n[i]);
    s.contact_flags = physics_out_.contact_flags |
                      (safety_.reasons() & firmware_host::kReasonPeakClamp ? 4u : 0u);
    s.penetration_m = float(physics_out_.penetration_m);
    s.period_ns = std::uint32_t(period > 0xFFFFFFFFu ? 0xFFFFFFFFu : period);
    s.compute_ns = compute_ns_max_;  // filled with the previous tick's work (this one runs now)
    s.jitter_ns = std::int32_t(std::int64_t(s.period_ns) - settings_.period_ns);
    s.overrun_count = std::uint32_t(stats_.overruns);
    s.passivity_power_w = float(physics_out_.dissipated_j / (double(settings_.period_ns) * 1e-9));
    s.safety_reasons = safety_.reasons();
    s.loop_flags = (safe_state_ ? ipc::kLoopFlagSafeState : 0u) |
                   (settings_.degraded_realtime ? ipc::kLoopFlagDegradedRt : 0u) |
                   (device_state_ == ipc::DeviceState::kReady ? 0u : ipc::kLoopFlagDeviceFault) |
                   (blade_.sensed() ? 0u : ipc::kLoopFlagFixedBlade) |
                   (checks_.tripped() ? ipc::kLoopFlagCheckFailed : 0u);
    producer_.publish_telemetry(s);

    ipc::LatestState st{};
    st.tick = tick_;
    st.time_ns = timing.start_ns;
    for (int i = 0; i < 3; ++i) {
        st.tool_position_m[i] = s.tool_position_m[i];
        st.force_n[i] = command_.force_n[i];
    }
    for (int i = 0; i < 4; ++i) st.tool_orientation_wxyz[i] = q[i];
    st.penetration_m = physics_out_.penetration_m;
    st.contact_flags = s.contact_flags;
    st.overrun_count = s.overrun_count;
    if (s.period_ns > period_ns_max_) period_ns_max_ = s.period_ns;
    st.period_ns_max = period_ns_max_;
    st.compute_ns_max = compute_ns_max_;
    producer_.publish_state(st);
    ++stats_.ticks;
}

void HapticLoop::publish_cut_events() noexcept {
    for (std::uint32_t i = 0; i < physics_out_.saw.event_count; ++i) {
        ipc::EventRecord r = cut_record(physics_out_.saw.events[i]);
        publish_event(r);
        if (r.header.type != ipc::EventType::kCutProgress) {
            log_.try_push(LogCode::kCutEvent, double(std::uint16_t(r.header.type)),
                          double(r.cut.cut_id));
        }
    }
}

void HapticLoop::publish_body_move() noexcept {
    if (!body_move_pending_) return;
    body_move_pending_ = false;
    ipc::EventRecord r{};
    r.header.type = ipc::EventType::kBodyMoved;
    r.body_moved.body_id = body_move_.body;
    const physics::RigidTransform& pose = body_move_.world_from_body;
    r.body_moved.position_m[0] = pose.translation.x;
    r.body_moved.position_m[1] = pose.translation.y;
    r.body_moved.position_m[2] = pose.translation.z;
    to_quaternion(pose.rotation, r.body_moved.orientation_wxyz);
    publish_event(r);
}

void HapticLoop::publish_device_state(ipc::DeviceState next) noexcept {
    ipc::EventRecord r{};
    r.header.type = ipc::EventType::kDeviceStateChanged;
    r.device.state = next;
    r.device.previous = device_state_;
    r.device.fault_flags =
        (sample_.flags.estop ? 1u : 0u) | (sample_.flags.watchdog_tripped ? 2u : 0u) |
        (sample_.flags.encoder_fault ? 4u : 0u) | (sample_.flags.over_temperature ? 8u : 0u) |
        (read_status_ == DeviceStatus::kDisconnected ? 16u : 0u) | (safe_state_ ? 32u : 0u);
    publish_event(r);
    log_.try_push(LogCode::kDeviceState, double(std::uint32_t(next)),
                  double(std::uint32_t(device_state_)));
    device_state_ = next;
}

void HapticLoop::publish_event(ipc::EventRecord& record) noexcept {
    const ipc::PublishOutcome out = producer_.publish_event(record);
    ++stats_.events_published;
    if (!out.journalled) {
        ++stats_.events_not_journalled;
        log_.try_push(LogCode::kEventNotJournalled, double(out.sequence),
                      double(stats_.events_not_journalled));
    }
}

}  // namespace kerf::rt
