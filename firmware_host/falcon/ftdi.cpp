#include "firmware_host/falcon/ftdi.hpp"

#include <algorithm>
#include <array>

namespace kerf::firmware_host::falcon {
namespace {

using namespace ftdi;

constexpr std::array<ControlRequest, 9> kFirmwareMode = {{
    {kReset, kPurgeRx},
    {kReset, kPurgeTx},
    {kLatencyTimer, 16},
    {kBaudDivisor, kBaud9600},
    {kDataFormat, kData8N1},
    {kFlowControl, 0},
    {kModemControl, kRtsLow},
    {kModemControl, kDtrLow},
    {kModemControl, kDtrHigh},
}};

constexpr std::array<ControlRequest, 2> kFirmwareLoad = {{
    {kModemControl, kDtrLow},
    {kBaudDivisor, kBaudFirmwareLoad},
}};

constexpr std::array<ControlRequest, 4> kNormalMode = {{
    {kLatencyTimer, 1},
    {kBaudDivisor, kBaudNormal},
    {kReset, kPurgeRx},
    {kReset, kPurgeTx},
}};

}  // namespace

std::size_t strip_ftdi_status(std::span<const std::byte> transfer,
                              std::span<std::byte> out) noexcept {
    std::size_t written = 0;
    for (std::size_t packet = 0; packet < transfer.size(); packet += kUsbPacketSize) {
        const std::size_t end = std::min(transfer.size(), packet + kUsbPacketSize);
        for (std::size_t i = packet + kFtdiStatusBytes; i < end && written < out.size(); ++i) {
            out[written++] = transfer[i];
        }
    }
    return written;
}

LinkStatus send_requests(UsbLink& link, std::span<const ControlRequest> requests,
                         std::uint32_t timeout_ms) noexcept {
    for (const auto& r : requests) {
        const auto s = link.control_transfer(kRequestType, r.request, r.value, 0, timeout_ms);
        if (s != LinkStatus::kOk) return s;
    }
    return LinkStatus::kOk;
}

std::span<const ControlRequest> firmware_mode_requests() noexcept { return kFirmwareMode; }
std::span<const ControlRequest> firmware_load_requests() noexcept { return kFirmwareLoad; }
std::span<const ControlRequest> normal_mode_requests() noexcept { return kNormalMode; }

}  // namespace kerf::firmware_host::falcon
