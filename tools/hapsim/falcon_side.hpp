// The device side of the Novint Falcon behind its FTDI bridge, byte for byte: the FTDI vendor
// control requests, 2 modem-status bytes on every bulk IN, the boot loader's handshake, baud
// probe and chunk echo, then the firmware's 16-byte normal-mode packets with homing.
#pragma once

#include <array>

#include "firmware_host/falcon/delta_kinematics.hpp"
#include "tools/hapsim/emulated_device.hpp"

namespace kerf::hapsim {

struct FalconSideParams {
    firmware_host::falcon::DeltaGeometry geometry;
    bool firmware_loaded = false;     ///< start with firmware running (as after a previous load)
    std::uint32_t homing_steps = 30;  ///< periods in homing mode before axis 0 homes (+5 per axis)
    bool lockstep = true;
};

class FalconSide final : public EmulatedDevice {
public:
    enum class Boot : std::uint8_t {
        kNoFirmware,
        kAwaitHandshake,
        kAwaitProbe,
        kLoading,
        kRunning
    };

    FalconSide(Simulation& sim, const FalconSideParams& params);

    void on_datagram(std::span<const std::byte> datagram, Outbox& out) override;
    void on_period(Outbox& out) override;
    void on_disconnect() override;
    Boot boot_state() const noexcept { return boot_; }

private:
    bool on_control(std::span<const std::byte> setup);
    void on_bulk_out(std::span<const std::byte> data, Outbox& out);
    void on_packet(std::span<const std::byte> data, Outbox& out);
    void step_and_report(Outbox& out);
    void push_in(std::span<const std::byte> payload, Outbox& out);
    Vec3 motor_force() const;

    Simulation& sim_;
    FalconSideParams p_;
    firmware_host::falcon::DeltaKinematics kin_;
    Boot boot_ = Boot::kNoFirmware;
    std::uint16_t baud_ = 0;
    bool dtr_ = false;
    std::size_t image_bytes_ = 0;
    bool image_bad_ = false;
    std::array<std::int16_t, 3> motor_{};
    bool homing_mode_ = false;
    std::array<std::uint32_t, 3> homing_steps_{};
    std::uint8_t homed_ = 0;
    std::array<std::int16_t, 3> counts_{};
    bool have_command_ = false;
};

}  // namespace kerf::hapsim
