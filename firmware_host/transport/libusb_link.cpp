#include "firmware_host/transport/libusb_link.hpp"

#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace kerf::firmware_host {

struct LibusbCallbacks {
    static void LIBUSB_CALL in_done(libusb_transfer* t) {
        auto* self = static_cast<LibusbLink*>(t->user_data);
        self->in_done_ = 1;
        if (t->status == LIBUSB_TRANSFER_NO_DEVICE)
            self->gone_.store(true, std::memory_order_release);
    }
    static void LIBUSB_CALL out_done(libusb_transfer* t) {
        auto* self = static_cast<LibusbLink*>(t->user_data);
        self->out_done_ = 1;
        if (t->status == LIBUSB_TRANSFER_NO_DEVICE)
            self->gone_.store(true, std::memory_order_release);
    }
    static int LIBUSB_CALL left(libusb_context*, libusb_device* device, libusb_hotplug_event,
                                void* user) {
        auto* self = static_cast<LibusbLink*>(user);
        if (self->handle_ != nullptr && libusb_get_device(self->handle_) == device) {
            self->gone_.store(true, std::memory_order_release);
        }
        return 0;  // stay registered
    }
};

namespace {

std::string ids(std::uint16_t vid, std::uint16_t pid) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "usb %04x:%04x", vid, pid);
    return buf;
}

std::string serial_of(libusb_device_handle* h, const libusb_device_descriptor& d) {
    unsigned char buf[128] = {};
    if (d.iSerialNumber == 0) return {};
    const int n = libusb_get_string_descriptor_ascii(h, d.iSerialNumber, buf, sizeof buf);
    return n > 0 ? std::string(reinterpret_cast<char*>(buf), static_cast<std::size_t>(n))
                 : std::string{};
}

LinkStatus from_libusb(int rc) noexcept {
    switch (rc) {
        case LIBUSB_SUCCESS:
            return LinkStatus::kOk;
        case LIBUSB_ERROR_TIMEOUT:
            return LinkStatus::kTimeout;
        case LIBUSB_ERROR_PIPE:
            return LinkStatus::kStall;
        case LIBUSB_ERROR_NO_DEVICE:
            return LinkStatus::kDisconnected;
        case LIBUSB_ERROR_OVERFLOW:
            return LinkStatus::kOverflow;
        case LIBUSB_ERROR_BUSY:
            return LinkStatus::kBusy;
        default:
            return rc > 0 ? LinkStatus::kOk : LinkStatus::kError;
    }
}

LinkStatus from_transfer(int status) noexcept {
    switch (status) {
        case LIBUSB_TRANSFER_COMPLETED:
            return LinkStatus::kOk;
        case LIBUSB_TRANSFER_TIMED_OUT:
            return LinkStatus::kTimeout;
        case LIBUSB_TRANSFER_STALL:
            return LinkStatus::kStall;
        case LIBUSB_TRANSFER_NO_DEVICE:
            return LinkStatus::kDisconnected;
        case LIBUSB_TRANSFER_OVERFLOW:
            return LinkStatus::kOverflow;
        default:
            return LinkStatus::kError;
    }
}

}  // namespace

Result<std::vector<UsbDeviceInfo>, TransportError> enumerate_usb(std::uint16_t vendor_id,
                                                                 std::uint16_t product_id) {
    libusb_context* ctx = nullptr;
    if (const int rc = libusb_init(&ctx); rc != 0) {
        return Err{transport_error(TransportErrc::kSystem, "libusb_init", "start libusb",
                                   libusb_strerror(rc))};
    }
    libusb_device** list = nullptr;
    const auto count = libusb_get_device_list(ctx, &list);
    std::vector<UsbDeviceInfo> out;
    for (ssize_t i = 0; i < count; ++i) {
        libusb_device_descriptor d{};
        if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
        if (d.idVendor != vendor_id || d.idProduct != product_id) continue;
        UsbDeviceInfo info{libusb_get_bus_number(list[i]),
                           libusb_get_device_address(list[i]),
                           d.idVendor,
                           d.idProduct,
                           {},
                           false};
        libusb_device_handle* h = nullptr;
        if (libusb_open(list[i], &h) == 0) {
            info.accessible = true;
            info.serial = serial_of(h, d);
            libusb_close(h);
        }
        out.push_back(std::move(info));
    }
    if (count >= 0) libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    if (count < 0) {
        return Err{transport_error(TransportErrc::kSystem, ids(vendor_id, product_id),
                                   "list USB devices", libusb_strerror(static_cast<int>(count)))};
    }
    return out;
}

namespace {

// The first matching device we may open, or why there is none.
Result<UsbDeviceInfo, TransportError> find_accessible(const UsbOpenSpec& spec,
                                                      const std::string& where) {
    auto found = enumerate_usb(spec.vendor_id, spec.product_id);
    if (!found) return Err{found.error()};
    const auto it = std::find_if(found->begin(), found->end(), [&](const UsbDeviceInfo& d) {
        return spec.serial.empty() || d.serial == spec.serial;
    });
    if (it == found->end()) {
        return Err{transport_error(TransportErrc::kNotConnected, where, "open USB device",
                                   "no such device connected")};
    }
    if (!it->accessible) {
        return Err{
            transport_error(TransportErrc::kNoPermission, where, "open USB device",
                            "permission denied (install config/udev rules, join group plugdev)")};
    }
    return *it;
}

}  // namespace

// Opens the device at bus/address on our own context; a libusb error code on failure.
int LibusbLink::open_handle(std::uint8_t bus, std::uint8_t address) noexcept {
    if (int rc = libusb_init(&ctx_); rc != 0) return rc;
    libusb_device** list = nullptr;
    const auto count = libusb_get_device_list(ctx_, &list);
    if (count < 0) return static_cast<int>(count);
    int rc = LIBUSB_ERROR_NO_DEVICE;  // it vanished between enumeration and open
    for (ssize_t i = 0; i < count && handle_ == nullptr; ++i) {
        if (libusb_get_bus_number(list[i]) == bus &&
            libusb_get_device_address(list[i]) == address) {
            rc = libusb_open(list[i], &handle_);
        }
    }
    libusb_free_device_list(list, 1);
    return rc;
}

// Claims interface 0, allocates both bulk transfers once, registers the unplug callback.
int LibusbLink::prepare(const UsbOpenSpec& spec) noexcept {
    libusb_set_auto_detach_kernel_driver(handle_, 1);  // ftdi_sio may have bound it
    if (int rc = libusb_claim_interface(handle_, 0); rc != 0) return rc;
    in_ = libusb_alloc_transfer(0);
    out_ = libusb_alloc_transfer(0);
    if (in_ == nullptr || out_ == nullptr) return LIBUSB_ERROR_NO_MEM;
    libusb_fill_bulk_transfer(in_, handle_, 0x81, in_buf_.data(), static_cast<int>(in_buf_.size()),
                              LibusbCallbacks::in_done, this, 0);
    libusb_fill_bulk_transfer(out_, handle_, 0x02, out_buf_.data(), 0, LibusbCallbacks::out_done,
                              this, 0);
    if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0) {
        hotplug_registered_ = libusb_hotplug_register_callback(
                                  ctx_, LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT, LIBUSB_HOTPLUG_NO_FLAGS,
                                  spec.vendor_id, spec.product_id, LIBUSB_HOTPLUG_MATCH_ANY,
                                  LibusbCallbacks::left, this, &hotplug_) == 0;
    }
    return 0;
}

Result<std::unique_ptr<LibusbLink>, TransportError> LibusbLink::open(const UsbOpenSpec& spec) {
    const std::string where = ids(spec.vendor_id, spec.product_id) +
                              (spec.serial.empty() ? "" : " serial " + spec.serial);
    auto device = find_accessible(spec, where);
    if (!device) return Err{device.error()};
    std::unique_ptr<LibusbLink> link(new LibusbLink());
    if (int rc = link->open_handle(device->bus, device->address); rc != 0) {
        return Err{
            transport_error(TransportErrc::kSystem, where, "open USB device", libusb_strerror(rc))};
    }
    if (int rc = link->prepare(spec); rc != 0) {
        return Err{transport_error(TransportErrc::kSystem, where,
                                   "claim interface 0 and set up transfers", libusb_strerror(rc))};
    }
    return link;
}

LibusbLink::~LibusbLink() {
    if (in_flight_ && in_ != nullptr) libusb_cancel_transfer(in_);
    if (out_flight_ && out_ != nullptr) libusb_cancel_transfer(out_);
    for (int i = 0; i < 100 && ((in_flight_ && in_done_ == 0) || (out_flight_ && out_done_ == 0));
         ++i) {
        timeval tv{0, 10000};
        libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
    }
    if (in_ != nullptr) libusb_free_transfer(in_);
    if (out_ != nullptr) libusb_free_transfer(out_);
    if (hotplug_registered_) libusb_hotplug_deregister_callback(ctx_, hotplug_);
    if (handle_ != nullptr) {
        libusb_release_interface(handle_, 0);
        libusb_close(handle_);
    }
    if (ctx_ != nullptr) libusb_exit(ctx_);
}

LinkStatus LibusbLink::control_transfer(std::uint8_t request_type, std::uint8_t request,
                                        std::uint16_t value, std::uint16_t index,
                                        std::uint32_t timeout_ms) noexcept {
    if (unplugged()) return LinkStatus::kDisconnected;
    const int rc = libusb_control_transfer(handle_, request_type, request, value, index, nullptr, 0,
                                           timeout_ms);
    return from_libusb(rc);
}

// Handles libusb events until `completed` is set or `timeout_us` passes.
LinkStatus LibusbLink::pump(int& completed, std::uint32_t timeout_us) noexcept {
    timeval tv{static_cast<time_t>(timeout_us / 1000000U),
               static_cast<suseconds_t>(timeout_us % 1000000U)};
    const int rc = libusb_handle_events_timeout_completed(ctx_, &tv, &completed);
    if (rc != 0 && rc != LIBUSB_ERROR_INTERRUPTED) return from_libusb(rc);
    return unplugged() ? LinkStatus::kDisconnected : LinkStatus::kOk;
}

LinkStatus LibusbLink::bulk_write(std::span<const std::byte> data,
                                  std::uint32_t timeout_ms) noexcept {
    if (unplugged()) return LinkStatus::kDisconnected;
    if (data.size() > out_buf_.size()) return LinkStatus::kOverflow;
    if (out_flight_ && out_done_ == 0) {
        if (auto s = pump(out_done_, timeout_ms * 1000U); s != LinkStatus::kOk) return s;
        if (out_done_ == 0) return LinkStatus::kBusy;
    }
    std::memcpy(out_buf_.data(), data.data(), data.size());
    out_->length = static_cast<int>(data.size());
    out_->timeout = timeout_ms == 0 ? 1000 : timeout_ms;
    out_done_ = 0;
    if (int rc = libusb_submit_transfer(out_); rc != 0) {
        out_flight_ = false;
        return from_libusb(rc);
    }
    out_flight_ = true;
    if (timeout_ms > 0) {
        if (auto s = pump(out_done_, timeout_ms * 1000U); s != LinkStatus::kOk) return s;
        if (out_done_ == 0) return LinkStatus::kTimeout;
        return from_transfer(out_->status);
    }
    return LinkStatus::kOk;
}

LinkStatus LibusbLink::bulk_read(std::span<std::byte> buffer, std::size_t& received,
                                 std::uint32_t timeout_us) noexcept {
    received = 0;
    if (unplugged()) return LinkStatus::kDisconnected;
    if (!in_flight_) {
        in_done_ = 0;
        if (int rc = libusb_submit_transfer(in_); rc != 0) return from_libusb(rc);
        in_flight_ = true;
    }
    if (in_done_ == 0) {
        if (auto s = pump(in_done_, timeout_us); s != LinkStatus::kOk) return s;
        if (in_done_ == 0) return LinkStatus::kTimeout;
    }
    in_flight_ = false;
    const auto status = from_transfer(in_->status);
    if (status != LinkStatus::kOk) return status;
    const auto n = static_cast<std::size_t>(in_->actual_length);
    if (n > buffer.size()) return LinkStatus::kOverflow;
    std::memcpy(buffer.data(), in_buf_.data(), n);
    received = n;
    in_done_ = 0;  // keep one IN transfer in flight, as the FTDI expects
    if (libusb_submit_transfer(in_) == 0) in_flight_ = true;
    return LinkStatus::kOk;
}

}  // namespace kerf::firmware_host
