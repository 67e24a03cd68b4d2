#include "firmware_host/transport/hidapi_transport.hpp"

#include <hidapi/hidapi.h>

#include <cstdio>
#include <cwchar>

namespace kerf::firmware_host {
namespace {

std::string narrow(const wchar_t* w) {
    std::string out;
    if (w == nullptr) return out;
    for (; *w != 0; ++w) out += (*w >= 0x20 && *w < 0x7F) ? static_cast<char>(*w) : '?';
    return out;
}

std::wstring widen(const std::string& s) { return std::wstring(s.begin(), s.end()); }

std::string ids(std::uint16_t vid, std::uint16_t pid) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "hid %04x:%04x", vid, pid);
    return buf;
}

bool init_hidapi(TransportError& error) {
    if (hid_init() == 0) return true;
    error = transport_error(TransportErrc::kSystem, "hid_init", "start hidapi",
                            narrow(hid_error(nullptr)));
    return false;
}

}  // namespace

Result<std::vector<HidDeviceInfo>, TransportError> enumerate_hid(std::uint16_t vendor_id,
                                                                 std::uint16_t product_id) {
    TransportError error;
    if (!init_hidapi(error)) return Err{error};
    std::vector<HidDeviceInfo> out;
    hid_device_info* list = hid_enumerate(vendor_id, product_id);
    for (auto* d = list; d != nullptr; d = d->next) {
        out.push_back({d->path ? d->path : "", d->vendor_id, d->product_id,
                       narrow(d->serial_number), narrow(d->manufacturer_string),
                       narrow(d->product_string)});
    }
    hid_free_enumeration(list);
    return out;
}

Result<std::unique_ptr<HidapiTransport>, TransportError> HidapiTransport::open(
    const HidOpenSpec& spec) {
    TransportError error;
    if (!init_hidapi(error)) return Err{error};
    hid_device* device = nullptr;
    std::string where;
    if (!spec.path.empty()) {
        where = spec.path;
        device = hid_open_path(spec.path.c_str());
    } else {
        where = ids(spec.vendor_id, spec.product_id) +
                (spec.serial.empty() ? "" : " serial " + spec.serial);
        const std::wstring serial = widen(spec.serial);
        device = hid_open(spec.vendor_id, spec.product_id,
                          spec.serial.empty() ? nullptr : serial.c_str());
    }
    if (device == nullptr) {
        const auto found = enumerate_hid(spec.vendor_id, spec.product_id);
        const bool none = found && found->empty() && spec.path.empty();
        return Err{none ? transport_error(TransportErrc::kNotConnected, where, "open HID device",
                                          "no such device connected")
                        : transport_error(TransportErrc::kNoPermission, where, "open HID device",
                                          "cannot open (permissions? install config/udev rules)")};
    }
    if (hid_set_nonblocking(device, 1) != 0) {
        hid_close(device);
        return Err{transport_error(TransportErrc::kSystem, where, "open HID device",
                                   "cannot set non-blocking mode")};
    }
    return std::unique_ptr<HidapiTransport>(new HidapiTransport(device));
}

HidapiTransport::~HidapiTransport() {
    if (device_ != nullptr) hid_close(device_);
}

LinkStatus HidapiTransport::try_write_report(std::span<const std::byte> report) noexcept {
    const int n =
        hid_write(device_, reinterpret_cast<const unsigned char*>(report.data()), report.size());
    return n < 0 ? LinkStatus::kDisconnected : LinkStatus::kOk;
}

LinkStatus HidapiTransport::read_report(std::span<std::byte> buffer, std::size_t& received,
                                        std::uint32_t timeout_us) noexcept {
    received = 0;
    const int timeout_ms = static_cast<int>((timeout_us + 999U) / 1000U);
    const int n = hid_read_timeout(device_, reinterpret_cast<unsigned char*>(buffer.data()),
                                   buffer.size(), timeout_ms);
    if (n < 0) return LinkStatus::kDisconnected;
    if (n == 0) return LinkStatus::kTimeout;
    received = static_cast<std::size_t>(n);
    return LinkStatus::kOk;
}

LinkStatus HidapiTransport::get_feature(std::uint8_t id, std::span<std::byte> buffer,
                                        std::size_t& received,
                                        std::uint32_t /*timeout_ms*/) noexcept {
    received = 0;
    if (buffer.empty()) return LinkStatus::kOverflow;
    buffer[0] = std::byte{id};
    const int n = hid_get_feature_report(device_, reinterpret_cast<unsigned char*>(buffer.data()),
                                         buffer.size());
    if (n < 0) return LinkStatus::kStall;
    received = static_cast<std::size_t>(n);
    return LinkStatus::kOk;
}

LinkStatus HidapiTransport::set_feature(std::span<const std::byte> report,
                                        std::uint32_t /*timeout_ms*/) noexcept {
    const int n = hid_send_feature_report(
        device_, reinterpret_cast<const unsigned char*>(report.data()), report.size());
    return n < 0 ? LinkStatus::kStall : LinkStatus::kOk;
}

}  // namespace kerf::firmware_host
