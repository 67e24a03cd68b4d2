// `kerf devices`: lists connected haptic devices — Novint Falcons through libusb (0403:cb48) and
// Kerf-protocol HID devices through hidapi (the vendor/product ids of every profile in
// config/devices/) — with their state (accessible or not) and the profile that matches them.
// Prints a clean "no haptic devices found" when there are none. `--json` for machines.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "config/data_dir.hpp"
#include "config/device_profile.hpp"
#include "firmware_host/falcon/ftdi.hpp"
#include "firmware_host/transport/hidapi_transport.hpp"
#include "firmware_host/transport/libusb_link.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/safe_text.hpp"

namespace kerf::cli {
namespace {

namespace fh = kerf::firmware_host;

struct Found {
    std::string kind;   ///< "falcon" or "kerf_hid"
    std::string where;  ///< "usb bus 1 address 5" or the hidraw path
    std::uint16_t vid = 0, pid = 0;
    std::string serial;
    std::string state;    ///< "ready" or "no permission (install config/udev rules)"
    std::string profile;  ///< matching profile name, or ""
};

std::string hex(std::uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof b, "%04x", v);
    return b;
}

std::string match_profile(const std::vector<config::NamedDeviceProfile>& profiles,
                          config::DeviceKind kind, std::uint16_t vid, std::uint16_t pid) {
    for (const auto& p : profiles) {
        if (p.profile.kind == kind && p.profile.ids.vendor_id == vid &&
            p.profile.ids.product_id == pid) {
            return p.profile_name;
        }
    }
    return {};
}

void list_falcons(const std::vector<config::NamedDeviceProfile>& profiles, std::vector<Found>& out,
                  std::vector<std::string>& errors) {
    auto usb = fh::enumerate_usb(fh::falcon::kFalconVendorId, fh::falcon::kFalconProductId);
    if (!usb) {
        errors.push_back(usb.error().message());
        return;
    }
    for (const auto& d : *usb) {
        out.push_back(
            {"falcon", "usb bus " + std::to_string(d.bus) + " address " + std::to_string(d.address),
             d.vendor_id, d.product_id, d.serial,
             d.accessible ? "ready" : "no permission (install config/udev rules)",
             match_profile(profiles, config::DeviceKind::kFalcon, d.vendor_id, d.product_id)});
    }
}

void list_hid(const std::vector<config::NamedDeviceProfile>& profiles, std::vector<Found>& out,
              std::vector<std::string>& errors) {
    std::set<std::pair<std::uint16_t, std::uint16_t>> ids;
    for (const auto& p : profiles) {
        if (p.profile.kind == config::DeviceKind::kKerfHid)
            ids.insert({p.profile.ids.vendor_id, p.profile.ids.product_id});
    }
    for (const auto& [vid, pid] : ids) {
        auto hid = fh::enumerate_hid(vid, pid);
        if (!hid) {
            errors.push_back(hid.error().message());
            return;
        }
        for (const auto& d : *hid) {
            out.push_back(
                {"kerf_hid", d.path, d.vendor_id, d.product_id, d.serial, "ready",
                 match_profile(profiles, config::DeviceKind::kKerfHid, d.vendor_id, d.product_id)});
        }
    }
}

/// The device-profile folder: --devices-dir if given; else the data folder's devices/
/// (config/data_dir.hpp: $KERF_DATA_DIR, installed share/kerf, the source tree's config/) — so
/// `kerf devices` works from any folder, installed or in-tree.
std::string find_devices_dir(const std::string& given) {
    if (!given.empty()) return given;
    return (config::data_dir() / "devices").string();
}

void print_text(const std::vector<Found>& found, const std::vector<std::string>& errors,
                const std::string& devices_dir, std::size_t hid_profiles) {
    for (const auto& e : errors) std::cerr << "kerf devices: " << safe_text(e) << "\n";
    if (found.empty()) {
        std::cout << "no haptic devices found (looked for Novint Falcon usb 0403:cb48";
        if (hid_profiles == 0) {
            std::cout << "; no Kerf HID profile in " << safe_text(devices_dir)
                      << ", so no Kerf HID ids to look for)\n";
        } else {
            std::cout << " and the Kerf HID ids of " << hid_profiles << " profile"
                      << (hid_profiles == 1 ? "" : "s") << " in " << safe_text(devices_dir)
                      << ")\n";
        }
        return;
    }
    for (const auto& f : found) {
        // Serial and path come from the device and the system: never raw to the terminal.
        std::cout << f.kind << "  " << hex(f.vid) << ":" << hex(f.pid) << "  " << safe_text(f.where)
                  << "  serial " << (f.serial.empty() ? "-" : safe_text(f.serial)) << "  "
                  << f.state << "  profile " << (f.profile.empty() ? "-" : f.profile) << "\n";
    }
}

/// One JSON document on stdout (nlohmann-json escapes every string; bytes that are not UTF-8 are
/// replaced, never passed through).
void print_json(const std::vector<Found>& found, const std::vector<std::string>& errors,
                const std::string& devices_dir) {
    nlohmann::ordered_json doc = {{"devices_dir", devices_dir},
                                  {"devices", nlohmann::ordered_json::array()},
                                  {"errors", errors}};
    for (const auto& f : found) {
        doc["devices"].push_back({{"kind", f.kind},
                                  {"vendor_id", hex(f.vid)},
                                  {"product_id", hex(f.pid)},
                                  {"where", f.where},
                                  {"serial", f.serial},
                                  {"state", f.state},
                                  {"profile", f.profile}});
    }
    std::cout << doc.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
}

}  // namespace

void add_devices_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("devices", "list connected haptic devices (Falcon, Kerf HID)");
    struct Options {
        std::string devices_dir;  // "": found (see find_devices_dir)
        bool json = false;
    };
    auto opts = std::make_shared<Options>();
    cmd->add_option("--devices-dir", opts->devices_dir,
                    "device profiles to match ids against (default: $KERF_DATA_DIR/devices, the "
                    "installed share/kerf/devices, then the source tree's config/devices)");
    cmd->add_flag("--json", opts->json, "machine-readable output");
    auto* dir_option = cmd->get_option("--devices-dir");
    cmd->callback([opts, dir_option] {
        if (dir_option->count() > 0 && opts->devices_dir.empty()) {
            std::cerr << "kerf devices: --devices-dir: an empty path (give a folder of device "
                         "profiles, or leave the option out)\n";
            throw CLI::RuntimeError(kExitUsage);
        }
        const std::string dir = find_devices_dir(opts->devices_dir);
        auto profiles = config::load_device_profiles(dir);
        if (!profiles) {
            std::cerr << "kerf devices: load device profiles: "
                      << safe_text(profiles.error().message()) << "\n";
            throw CLI::RuntimeError(kExitFailure);
        }
        std::vector<Found> found;
        std::vector<std::string> errors;
        list_falcons(*profiles, found, errors);
        list_hid(*profiles, found, errors);
        std::size_t hid_profiles = 0;
        for (const auto& p : *profiles)
            hid_profiles += p.profile.kind == config::DeviceKind::kKerfHid ? 1 : 0;
        opts->json ? print_json(found, errors, dir) : print_text(found, errors, dir, hid_profiles);
        if (errors.size() >= 2) throw CLI::RuntimeError(kExitFailure);  // neither backend worked
    });
}

}  // namespace kerf::cli
