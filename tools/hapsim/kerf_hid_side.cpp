#include "tools/hapsim/kerf_hid_side.hpp"

#include <algorithm>
#include <cmath>

#include "firmware_host/transport/socket_tags.hpp"

namespace kerf::hapsim {

namespace fh = kerf::firmware_host;
using Clock = std::chrono::steady_clock;

KerfHidSide::KerfHidSide(Simulation& sim, const KerfSideParams& params) : sim_(sim), p_(params) {}

bool KerfHidSide::latched_fault() const {
    return watchdog_tripped_ || encoder_fault_latched_ || estop_latched_;
}

std::uint16_t KerfHidSide::status() const {
    std::uint16_t s = 0;
    const bool amps = config_.amplifier_enable && amp_flag_ && homed_ && !latched_fault();
    if (amps) s |= fh::kStatusAmplifiersOn;
    if (homed_) s |= fh::kStatusHomed;
    if (estop_latched_) s |= fh::kStatusEStop;
    if (watchdog_tripped_) s |= fh::kStatusWatchdogTripped;
    if (encoder_fault_latched_) s |= fh::kStatusEncoderFault;
    if (homing_) s |= fh::kStatusHoming;
    return s;
}

void KerfHidSide::on_output(const fh::OutputReport& rep) {
    echo_ = rep.sequence;
    have_output_ = true;
    last_valid_ = Clock::now();
    const bool zero = rep.command_milli == std::array<std::int32_t, 3>{0, 0, 0};
    if ((rep.flags & fh::kFlagClearFault) != 0 && zero) {
        watchdog_tripped_ = false;
        if (!sim_.faults().estop) estop_latched_ = false;
        if (!sim_.faults().stuck_encoder) encoder_fault_latched_ = false;
    }
    if ((rep.flags & fh::kFlagStartHoming) != 0 && !homed_ && !homing_) {
        homing_ = true;
        homing_left_ = p_.homing_steps;
    }
    amp_flag_ = (rep.flags & fh::kFlagAmplifierEnable) != 0;
    for (int i = 0; i < 3; ++i) command_n_[i] = rep.command_milli[i] * 1e-3;
}

void KerfHidSide::step_and_report(Outbox& out) {
    auto& faults = sim_.faults();
    if (faults.watchdog_trip) {
        watchdog_tripped_ = true;
        faults.watchdog_trip = false;
    }
    if (faults.estop) estop_latched_ = true;
    if (faults.stuck_encoder) encoder_fault_latched_ = true;
    if (homing_ && homing_left_ > 0 && --homing_left_ == 0) {
        homing_ = false;
        homed_ = true;
    }
    Vec3 force{};
    if ((status() & fh::kStatusAmplifiersOn) != 0) {
        const double mag = std::sqrt(command_n_[0] * command_n_[0] + command_n_[1] * command_n_[1] +
                                     command_n_[2] * command_n_[2]);
        const double s = mag > p_.peak_force_n ? p_.peak_force_n / mag : 1.0;
        for (int i = 0; i < 3; ++i) force[i] = command_n_[i] * s;
    }
    sim_.step(force);
    fh::InputReport in;
    in.sequence = ++in_sequence_;
    in.echo_sequence = echo_;
    in.status = status();
    in.device_time_us = static_cast<std::uint32_t>(
        sim_.steps() * static_cast<std::uint64_t>(sim_.period_s() * 1e6));
    const auto& x = sim_.model().position_m();
    const auto& v = sim_.model().velocity_m_per_s();
    for (int i = 0; i < 3; ++i) {
        const double q = std::round(x[i] / p_.resolution_m) * p_.resolution_m;
        const auto um = static_cast<std::int32_t>(std::llround(q * 1e6));
        in.position[i] = faults.stuck_encoder ? frozen_um_[i] : um;
        if (!faults.stuck_encoder) frozen_um_[i] = um;
        in.velocity[i] =
            static_cast<std::int32_t>(std::llround(std::clamp(v[i], -100.0, 100.0) * 1e6));
        in.applied_centi[i] =
            static_cast<std::int16_t>(std::lround(sim_.model().applied_force_n()[i] * 100));
    }
    in.buttons = static_cast<std::uint16_t>(sim_.hand().buttons());
    in.temperature_centi_c = 3100;
    if (p_.mechanics.senses_orientation) {  // a 6-DoF-in device: the hand's tool orientation
        const auto& q = sim_.hand().orientation_wxyz();
        for (int i = 0; i < 4; ++i) in.orientation_q15[i] = std::int16_t(std::lround(q[i] * 32767));
    }
    std::array<std::byte, fh::kReportSize> buf{};
    if (fh::encode_input(in, buf) == fh::CodecStatus::kOk) out.push(fh::tag::kIn, buf);
}

void KerfHidSide::on_feature_get(std::uint8_t id, Outbox& out) {
    std::array<std::byte, fh::kReportSize> buf{};
    fh::CodecStatus s = fh::CodecStatus::kBadReportId;
    if (id == static_cast<std::uint8_t>(fh::ReportId::kIdentity))
        s = fh::encode_identity(p_.identity, buf);
    if (id == static_cast<std::uint8_t>(fh::ReportId::kMechanics))
        s = fh::encode_mechanics(p_.mechanics, buf);
    if (id == static_cast<std::uint8_t>(fh::ReportId::kConfig)) s = fh::encode_config(config_, buf);
    if (s == fh::CodecStatus::kOk) {
        out.push(fh::tag::kFeature, buf);
    } else {
        out.push(fh::tag::kFeature, {});  // refused (a USB stall)
    }
}

void KerfHidSide::on_feature_set(std::span<const std::byte> report, Outbox& out) {
    fh::ConfigReport c;
    const bool ok = fh::decode_config(report, c) == fh::CodecStatus::kOk;
    if (ok) config_ = c;
    const std::byte reply[1] = {std::byte{static_cast<std::uint8_t>(ok ? 1 : 0)}};
    out.push(fh::tag::kSetReply, reply);
}

void KerfHidSide::on_datagram(std::span<const std::byte> d, Outbox& out) {
    if (d.empty()) return;
    const auto body = d.subspan(1);
    if (d[0] == fh::tag::kGetFeature && body.size() == 1) {
        on_feature_get(std::to_integer<std::uint8_t>(body[0]), out);
    } else if (d[0] == fh::tag::kSetFeature) {
        on_feature_set(body, out);
    } else if (d[0] == fh::tag::kOut) {
        fh::OutputReport rep;
        if (fh::decode_output(body, rep) == fh::CodecStatus::kOk) on_output(rep);
        if (p_.lockstep) step_and_report(out);  // one step per host packet, valid or not
    }
}

void KerfHidSide::on_period(Outbox& out) {
    // Device-side watchdog on the wall clock (real-time mode only: lockstep time stands still).
    if (have_output_ && !watchdog_tripped_ &&
        Clock::now() - last_valid_ > std::chrono::milliseconds(config_.watchdog_ms)) {
        watchdog_tripped_ = true;
    }
    step_and_report(out);
}

void KerfHidSide::on_disconnect() {
    config_ = {};
    command_n_ = {};
    amp_flag_ = false;
    have_output_ = false;
    homing_ = false;  // a replugged device keeps its homing (absolute reference survives)
}

}  // namespace kerf::hapsim
