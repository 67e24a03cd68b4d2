// The device side of Kerf's HID protocol (PROTOCOL.md §3–§5), byte for byte: feature reports,
// output reports, the latched device-side watchdog, homing, e-stop and encoder-fault bits.
#pragma once

#include <chrono>

#include "firmware_host/protocol/kerf_hid_codec.hpp"
#include "tools/hapsim/emulated_device.hpp"

namespace kerf::hapsim {

struct KerfSideParams {
    firmware_host::IdentityReport identity;
    firmware_host::MechanicsReport mechanics;
    double resolution_m = 1e-5;       ///< position quantum (Cartesian)
    double peak_force_n = 10.0;       ///< the device's own clamp
    std::uint32_t homing_steps = 20;  ///< periods homing takes
    bool lockstep = true;
};

class KerfHidSide final : public EmulatedDevice {
public:
    KerfHidSide(Simulation& sim, const KerfSideParams& params);

    void on_datagram(std::span<const std::byte> datagram, Outbox& out) override;
    void on_period(Outbox& out) override;
    void on_disconnect() override;

private:
    void on_output(const firmware_host::OutputReport& rep);
    void on_feature_get(std::uint8_t id, Outbox& out);
    void on_feature_set(std::span<const std::byte> report, Outbox& out);
    void step_and_report(Outbox& out);
    std::uint16_t status() const;
    bool latched_fault() const;

    Simulation& sim_;
    KerfSideParams p_;
    firmware_host::ConfigReport config_;
    Vec3 command_n_{};
    bool amp_flag_ = false;
    bool homed_ = false;
    bool homing_ = false;
    std::uint32_t homing_left_ = 0;
    bool watchdog_tripped_ = false;
    bool encoder_fault_latched_ = false;
    bool estop_latched_ = false;
    std::uint16_t in_sequence_ = 0;
    std::uint16_t echo_ = 0;
    bool have_output_ = false;
    std::chrono::steady_clock::time_point last_valid_{};
    std::array<std::int32_t, 3> frozen_um_{};
};

}  // namespace kerf::hapsim
