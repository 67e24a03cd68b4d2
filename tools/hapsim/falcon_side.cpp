#include "tools/hapsim/falcon_side.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "firmware_host/falcon/falcon_packet.hpp"
#include "firmware_host/falcon/ftdi.hpp"
#include "firmware_host/transport/socket_tags.hpp"

namespace kerf::hapsim {

namespace fh = kerf::firmware_host;
namespace fal = kerf::firmware_host::falcon;

namespace {

constexpr std::array<std::byte, 2> kModemStatus = {std::byte{0x31}, std::byte{0x60}};
constexpr std::array<std::int16_t, 3> kUnhomedOffset = {137, -59, 211};  // relative encoders

std::uint16_t u16(std::span<const std::byte> b, std::size_t at) {
    return static_cast<std::uint16_t>(std::to_integer<unsigned>(b[at]) |
                                      (std::to_integer<unsigned>(b[at + 1]) << 8));
}

}  // namespace

FalconSide::FalconSide(Simulation& sim, const FalconSideParams& params)
    : sim_(sim), p_(params), kin_(params.geometry) {
    if (p_.firmware_loaded) boot_ = Boot::kRunning;
}

void FalconSide::push_in(std::span<const std::byte> payload, Outbox& out) {
    std::vector<std::byte> t(kModemStatus.begin(), kModemStatus.end());
    t.insert(t.end(), payload.begin(), payload.end());
    out.push(fh::tag::kIn, t);
}

// FTDI vendor requests; returns false to stall an unknown one.
bool FalconSide::on_control(std::span<const std::byte> setup) {
    if (setup.size() != 6 || setup[0] != std::byte{fal::ftdi::kRequestType}) return false;
    const auto request = std::to_integer<std::uint8_t>(setup[1]);
    const auto value = u16(setup, 2);
    switch (request) {
        case fal::ftdi::kReset:
            return value <= 2;
        case fal::ftdi::kModemControl:
            if ((value & 0x0100) != 0) dtr_ = (value & 0x0001) != 0;
            if (dtr_ && baud_ == fal::ftdi::kBaud9600) {  // the boot loader restarts
                boot_ = Boot::kAwaitHandshake;
                image_bytes_ = 0;
                image_bad_ = false;
                homed_ = 0;
            }
            return true;
        case fal::ftdi::kBaudDivisor:
            baud_ = value;
            if (value == fal::ftdi::kBaudNormal && boot_ == Boot::kLoading && image_bytes_ > 0 &&
                !image_bad_) {
                boot_ = Boot::kRunning;  // the loaded firmware starts
            }
            return true;
        case fal::ftdi::kFlowControl:
        case fal::ftdi::kDataFormat:
        case fal::ftdi::kLatencyTimer:
            return true;
        default:
            return false;
    }
}

void FalconSide::on_bulk_out(std::span<const std::byte> data, Outbox& out) {
    auto& faults = sim_.faults();
    switch (boot_) {
        case Boot::kNoFirmware:
            return;  // nobody answers
        case Boot::kAwaitHandshake: {
            const std::array<std::byte, 3> hello = {std::byte{0x0A}, std::byte{0x43},
                                                    std::byte{0x0D}};
            if (data.size() == 3 && std::equal(data.begin(), data.end(), hello.begin())) {
                const std::array<std::byte, 5> reply = {std::byte{0x00}, std::byte{0x0A},
                                                        std::byte{0x44}, std::byte{0x2C},
                                                        std::byte{0x0D}};
                push_in(reply, out);
                boot_ = Boot::kAwaitProbe;
            }
            return;
        }
        case Boot::kAwaitProbe:
            if (baud_ == fal::ftdi::kBaudFirmwareLoad && !dtr_ && data.size() == 1 &&
                data[0] == std::byte{0x41}) {
                push_in(data, out);
                boot_ = Boot::kLoading;
            }
            return;
        case Boot::kLoading: {
            std::vector<std::byte> echo(data.begin(), data.end());
            if ((faults.firmware_fail || faults.echo_mismatch_left > 0) && !echo.empty()) {
                echo[echo.size() / 2] ^= std::byte{0x5A};
                image_bad_ = true;
                if (faults.echo_mismatch_left > 0) --faults.echo_mismatch_left;
            }
            image_bytes_ += data.size();
            push_in(echo, out);
            return;
        }
        case Boot::kRunning:
            on_packet(data, out);
            return;
    }
}

void FalconSide::on_packet(std::span<const std::byte> data, Outbox& out) {
    fal::FalconCommand cmd;
    if (fal::decode_command(data, cmd) != fal::FalconCodecStatus::kOk) return;
    motor_ = cmd.motor;
    homing_mode_ = cmd.homing_mode;
    have_command_ = true;
    if (p_.lockstep) step_and_report(out);
}

Vec3 FalconSide::motor_force() const {
    if (homed_ != 0x7) return {};  // the firmware drives no force before homing
    Vec3 theta{}, force{};
    const auto& x = sim_.model().position_m();
    if (kin_.inverse(x, theta) != fal::KinematicsStatus::kOk) return {};
    Vec3 torque{};
    for (int i = 0; i < 3; ++i) torque[i] = motor_[i] / p_.geometry.command_per_n_m;
    if (kin_.force_from_torques(theta, x, torque, force) != fal::KinematicsStatus::kOk) return {};
    return force;
}

void FalconSide::step_and_report(Outbox& out) {
    for (int i = 0; i < 3; ++i) {
        if (homing_mode_ && (homed_ & (1U << i)) == 0 &&
            ++homing_steps_[i] >= p_.homing_steps + 5U * i) {
            homed_ |= static_cast<std::uint8_t>(1U << i);
        }
    }
    sim_.step(motor_force());
    Vec3 theta{};
    if (!sim_.faults().stuck_encoder &&
        kin_.inverse(sim_.model().position_m(), theta) == fal::KinematicsStatus::kOk) {
        for (int i = 0; i < 3; ++i) {
            const auto c =
                kin_.counts(theta[i]) + ((homed_ & (1U << i)) != 0 ? 0 : kUnhomedOffset[i]);
            counts_[i] = static_cast<std::int16_t>(std::clamp(c, -32768, 32767));
        }
    }
    fal::FalconReport rep;
    rep.encoder = counts_;
    rep.homed = homed_;
    rep.buttons = static_cast<std::uint8_t>(sim_.hand().buttons() & 0xF);
    std::array<std::byte, fal::kPacketSize> buf{};
    (void)fal::encode_report(rep, buf);
    push_in(buf, out);
}

void FalconSide::on_datagram(std::span<const std::byte> d, Outbox& out) {
    if (d.empty()) return;
    if (d[0] == fh::tag::kControl) {
        const std::byte ok[1] = {
            std::byte{static_cast<std::uint8_t>(on_control(d.subspan(1)) ? 1 : 0)}};
        out.push(fh::tag::kControlReply, ok);
    } else if (d[0] == fh::tag::kOut) {
        on_bulk_out(d.subspan(1), out);
    }
}

void FalconSide::on_period(Outbox& out) {
    if (boot_ == Boot::kRunning && have_command_) step_and_report(out);
}

void FalconSide::on_disconnect() {
    motor_ = {};
    have_command_ = false;
    homing_mode_ = false;
    boot_ = p_.firmware_loaded ? Boot::kRunning : Boot::kNoFirmware;  // power lost on unplug
    homed_ = 0;
    homing_steps_ = {};
}

}  // namespace kerf::hapsim
