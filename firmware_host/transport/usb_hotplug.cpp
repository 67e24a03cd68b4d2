#include "firmware_host/transport/usb_hotplug.hpp"

#include <libusb-1.0/libusb.h>

#include <cstdio>

namespace kerf::firmware_host {

struct UsbHotplugMonitor::Callbacks {
    static int LIBUSB_CALL on_event(libusb_context*, libusb_device*, libusb_hotplug_event event,
                                    void* user) {
        auto* self = static_cast<UsbHotplugMonitor*>(user);
        if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED) ++self->counts_.arrived;
        if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT) ++self->counts_.left;
        return 0;
    }
};

Result<std::unique_ptr<UsbHotplugMonitor>, TransportError> UsbHotplugMonitor::create(
    std::uint16_t vendor_id, std::uint16_t product_id) {
    char where[32];
    std::snprintf(where, sizeof where, "usb %04x:%04x", vendor_id, product_id);
    std::unique_ptr<UsbHotplugMonitor> m(new UsbHotplugMonitor());
    if (int rc = libusb_init(&m->ctx_); rc != 0) {
        return Err{
            transport_error(TransportErrc::kSystem, where, "start libusb", libusb_strerror(rc))};
    }
    if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) == 0) {
        return Err{transport_error(TransportErrc::kUnsupported, where, "watch hotplug",
                                   "this libusb has no hotplug support")};
    }
    const auto events = static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                                          LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT);
    const int rc = libusb_hotplug_register_callback(m->ctx_, events, LIBUSB_HOTPLUG_ENUMERATE,
                                                    vendor_id, product_id, LIBUSB_HOTPLUG_MATCH_ANY,
                                                    Callbacks::on_event, m.get(), &m->handle_);
    if (rc != 0)
        return Err{
            transport_error(TransportErrc::kSystem, where, "watch hotplug", libusb_strerror(rc))};
    m->registered_ = true;
    return m;
}

UsbHotplugMonitor::~UsbHotplugMonitor() {
    if (registered_) libusb_hotplug_deregister_callback(ctx_, handle_);
    if (ctx_ != nullptr) libusb_exit(ctx_);
}

HotplugCounts UsbHotplugMonitor::poll(std::uint32_t timeout_us) noexcept {
    timeval tv{static_cast<time_t>(timeout_us / 1000000U),
               static_cast<suseconds_t>(timeout_us % 1000000U)};
    libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
    const HotplugCounts out = counts_;
    counts_ = {};
    return out;
}

}  // namespace kerf::firmware_host
