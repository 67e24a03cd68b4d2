// LibusbLink — UsbLink on real hardware through libusb-1.0: the Falcon's FTDI interface 0,
// bulk OUT 0x02 / IN 0x81. The two bulk transfers and their buffers are allocated once at open
// and reused for every packet (libnifalcon's per-packet allocation is the flaw this avoids); the
// IN transfer stays in flight. A hotplug callback marks the link disconnected on unplug.
// Note: libusb's Linux backend itself allocates its URB array inside libusb_submit_transfer.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "firmware_host/transport/transport_error.hpp"
#include "firmware_host/transport/usb_link.hpp"

struct libusb_context;
struct libusb_device_handle;
struct libusb_transfer;

namespace kerf::firmware_host {

/// One USB device libusb sees.
struct UsbDeviceInfo {
    std::uint8_t bus = 0;
    std::uint8_t address = 0;
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::string serial;       ///< empty when the device could not be opened to read it
    bool accessible = false;  ///< we could open it (udev rules / permissions)
};

/// Every USB device with these ids, or an error when libusb cannot start.
Result<std::vector<UsbDeviceInfo>, TransportError> enumerate_usb(std::uint16_t vendor_id,
                                                                 std::uint16_t product_id);

struct UsbOpenSpec {
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::string serial;  ///< empty: the first matching device
};

class LibusbLink final : public UsbLink {
public:
    static Result<std::unique_ptr<LibusbLink>, TransportError> open(const UsbOpenSpec& spec);
    ~LibusbLink() override;
    LibusbLink(const LibusbLink&) = delete;
    LibusbLink& operator=(const LibusbLink&) = delete;

    LinkStatus control_transfer(std::uint8_t request_type, std::uint8_t request,
                                std::uint16_t value, std::uint16_t index,
                                std::uint32_t timeout_ms) noexcept override;
    LinkStatus bulk_write(std::span<const std::byte> data,
                          std::uint32_t timeout_ms) noexcept override;
    LinkStatus bulk_read(std::span<std::byte> buffer, std::size_t& received,
                         std::uint32_t timeout_us) noexcept override;

    /// True once the hotplug callback or a transfer reported the device gone.
    bool unplugged() const noexcept { return gone_.load(std::memory_order_acquire); }

    struct State;  ///< transfer bookkeeping shared with the libusb callbacks (in the .cpp)

private:
    LibusbLink() = default;
    int open_handle(std::uint8_t bus, std::uint8_t address) noexcept;
    int prepare(const UsbOpenSpec& spec) noexcept;
    LinkStatus pump(int& completed, std::uint32_t timeout_us) noexcept;

    libusb_context* ctx_ = nullptr;
    libusb_device_handle* handle_ = nullptr;
    libusb_transfer* in_ = nullptr;
    libusb_transfer* out_ = nullptr;
    int hotplug_ = 0;
    bool hotplug_registered_ = false;
    bool in_flight_ = false;
    bool out_flight_ = false;
    int in_done_ = 0;
    int out_done_ = 0;
    std::atomic<bool> gone_{false};
    std::array<unsigned char, 512> in_buf_{};
    std::array<unsigned char, 64> out_buf_{};

    friend struct LibusbCallbacks;
};

}  // namespace kerf::firmware_host
