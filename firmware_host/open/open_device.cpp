#include "firmware_host/open/open_device.hpp"

#include <algorithm>

#include "config/expand_path.hpp"
#include "firmware_host/transport/hidapi_transport.hpp"
#include "firmware_host/transport/libusb_link.hpp"
#include "firmware_host/transport/socket_report_transport.hpp"
#include "firmware_host/transport/socket_usb_link.hpp"

namespace kerf::firmware_host {

SafetyLimits safety_limits_from(const config::DeviceProfile& device,
                                const config::ForceProfile* force, double period_s) {
    SafetyLimits l;
    l.period_s = period_s;
    l.peak_force_n = device.limits.peak_force_n;
    l.continuous_force_n = device.limits.continuous_force_n;
    l.max_slew_n_per_s = device.limits.max_slew_n_per_s;
    // A device without a watchdog of its own gets a host-side one: stale after watchdog_ms.
    const auto stale = static_cast<std::uint32_t>(device.limits.watchdog_ms * 1e-3 / period_s);
    l.stale_ticks = std::clamp<std::uint32_t>(stale, 1U, 2U);
    if (force != nullptr) {
        const auto& f = force->limits;
        if (f.max_force_n > 0) l.peak_force_n = std::min(l.peak_force_n, f.max_force_n);
        l.continuous_force_n = std::min(l.continuous_force_n, l.peak_force_n);
        if (f.slew_rate_n_per_s > 0)
            l.max_slew_n_per_s = std::min(l.max_slew_n_per_s, f.slew_rate_n_per_s);
        l.ramp_in_s = f.ramp_in_s;
        l.engage_threshold_n = f.engage_threshold_n;
        l.engage_quiet_ticks = f.engage_quiet_ticks;
    }
    return l;
}

falcon::DeltaGeometry delta_geometry_from(const config::DeviceProfile& device) {
    const auto& k = device.falcon_delta;
    falcon::DeltaGeometry g;
    g.a_m = k.a_m;
    g.b_m = k.b_m;
    g.c_m = k.c_m;
    g.d_m = k.d_m;
    g.e_m = k.e_m;
    g.f_m = k.f_m;
    g.r_m = k.r_m;
    g.s_m = k.s_m;
    g.leg_angles_deg = k.leg_angles_deg;
    g.theta_offset_deg = k.theta_offset_deg;
    g.counts_per_rev = device.encoder.counts_per_rev;
    g.shaft_diameter_m = device.encoder.shaft_diameter_m;
    g.drum_diameter_m = device.encoder.drum_diameter_m;
    g.command_per_n_m = device.motor.command_per_n_m;
    g.command_limit = device.motor.command_limit;
    return g;
}

KerfHidOptions kerf_hid_options_from(const config::DeviceProfile& device) {
    KerfHidOptions o;
    o.watchdog_ms =
        static_cast<std::uint16_t>(std::clamp<std::uint32_t>(device.limits.watchdog_ms, 1U, 1000U));
    o.expected_vendor_id = device.ids.vendor_id;
    o.expected_product_id = device.ids.product_id;
    return o;
}

namespace {

Result<std::unique_ptr<Device>, TransportError> open_falcon(std::unique_ptr<UsbLink> link,
                                                            const config::DeviceProfile& p,
                                                            const OpenOverrides& o) {
    FalconOptions options;
    // A simulated profile may describe no delta: the emulator then uses libnifalcon's figures.
    if (p.kinematic_model == config::KinematicModel::kFalconDelta)
        options.geometry = delta_geometry_from(p);
    options.firmware_path = o.firmware_path;
    auto dev = FalconDevice::open(std::move(link), options);
    if (!dev) return Err{dev.error()};
    return std::unique_ptr<Device>(std::move(*dev));
}

Result<std::unique_ptr<Device>, TransportError> open_kerf(std::unique_ptr<ReportTransport> t,
                                                          const config::DeviceProfile& p) {
    auto dev = KerfHidDevice::open(std::move(t), kerf_hid_options_from(p));
    if (!dev) return Err{dev.error()};
    return std::unique_ptr<Device>(std::move(*dev));
}

}  // namespace

Result<std::unique_ptr<Device>, TransportError> open_device(const config::DeviceProfile& p,
                                                            const OpenOverrides& o) {
    switch (p.kind) {
        case config::DeviceKind::kFalcon: {
            auto link = LibusbLink::open({p.ids.vendor_id, p.ids.product_id, p.ids.serial});
            if (!link) return Err{link.error()};
            return open_falcon(std::move(*link), p, o);
        }
        case config::DeviceKind::kKerfHid: {
            auto t = HidapiTransport::open(
                {p.ids.vendor_id, p.ids.product_id, p.ids.serial, o.hid_path});
            if (!t) return Err{t.error()};
            return open_kerf(std::move(*t), p);
        }
        case config::DeviceKind::kSimulated:
            break;
    }
    std::string path = o.socket_path;
    if (path.empty()) {
        auto expanded = config::expand_path(p.emulator.socket_path, {});
        if (!expanded)
            return Err{transport_error(TransportErrc::kConfig, p.emulator.socket_path,
                                       "expand emulator socket path", expanded.error().message())};
        path = expanded->string();
    }
    auto socket = SeqpacketSocket::connect(path);
    if (!socket) return Err{socket.error()};
    if (p.emulator.protocol == config::DeviceKind::kFalcon) {
        return open_falcon(std::make_unique<SocketUsbLink>(std::move(*socket)), p, o);
    }
    return open_kerf(std::make_unique<SocketReportTransport>(std::move(*socket)), p);
}

}  // namespace kerf::firmware_host
