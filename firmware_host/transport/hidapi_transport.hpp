// HidapiTransport — Kerf HID reports over hidapi (hidraw backend). Devices are found by the
// vendor/product ids of their profile (config/devices/*.toml) and opened by hidraw path or
// serial number. Reads are non-blocking (hid_read_timeout 0) or bounded to whole milliseconds.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "firmware_host/transport/report_transport.hpp"
#include "firmware_host/transport/transport_error.hpp"

struct hid_device_;

namespace kerf::firmware_host {

/// One HID device hidapi sees.
struct HidDeviceInfo {
    std::string path;  ///< e.g. /dev/hidraw3
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::string serial;  ///< may be empty
    std::string manufacturer;
    std::string product;
};

/// Every HID device with these ids (0 = any), or an error when hidapi cannot start.
Result<std::vector<HidDeviceInfo>, TransportError> enumerate_hid(std::uint16_t vendor_id,
                                                                 std::uint16_t product_id);

/// Which device to open: `path` wins; else the first with `serial` (empty: any) and the ids.
struct HidOpenSpec {
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::string serial;
    std::string path;
};

class HidapiTransport final : public ReportTransport {
public:
    static Result<std::unique_ptr<HidapiTransport>, TransportError> open(const HidOpenSpec& spec);
    ~HidapiTransport() override;
    HidapiTransport(const HidapiTransport&) = delete;
    HidapiTransport& operator=(const HidapiTransport&) = delete;

    LinkStatus try_write_report(std::span<const std::byte> report) noexcept override;
    LinkStatus read_report(std::span<std::byte> buffer, std::size_t& received,
                           std::uint32_t timeout_us) noexcept override;
    LinkStatus get_feature(std::uint8_t id, std::span<std::byte> buffer, std::size_t& received,
                           std::uint32_t timeout_ms) noexcept override;
    LinkStatus set_feature(std::span<const std::byte> report,
                           std::uint32_t timeout_ms) noexcept override;

private:
    explicit HidapiTransport(hid_device_* device) noexcept : device_(device) {}
    hid_device_* device_ = nullptr;
};

}  // namespace kerf::firmware_host
