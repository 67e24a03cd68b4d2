// UsbHotplugMonitor — arrival and departure of USB devices with given ids, through libusb's
// hotplug API (libusb_hotplug_register_callback). Off the real-time thread: the loop's owner
// polls it (e.g. every 100 ms) to re-open a Falcon that was unplugged and plugged back.
#pragma once

#include <cstdint>
#include <memory>

#include "config/base/result.hpp"
#include "firmware_host/transport/transport_error.hpp"

struct libusb_context;

namespace kerf::firmware_host {

struct HotplugCounts {
    std::uint32_t arrived = 0;
    std::uint32_t left = 0;
};

class UsbHotplugMonitor {
public:
    /// Registers for devices `vendor_id:product_id`; an error when libusb has no hotplug support.
    static Result<std::unique_ptr<UsbHotplugMonitor>, TransportError> create(
        std::uint16_t vendor_id, std::uint16_t product_id);
    ~UsbHotplugMonitor();
    UsbHotplugMonitor(const UsbHotplugMonitor&) = delete;
    UsbHotplugMonitor& operator=(const UsbHotplugMonitor&) = delete;

    /// Handles pending libusb events for at most `timeout_us`; returns the events since last call.
    HotplugCounts poll(std::uint32_t timeout_us) noexcept;

    struct Callbacks;

private:
    UsbHotplugMonitor() = default;
    libusb_context* ctx_ = nullptr;
    int handle_ = 0;
    bool registered_ = false;
    HotplugCounts counts_;
};

}  // namespace kerf::firmware_host
