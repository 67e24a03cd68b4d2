// TransportError — why a transport or device could not be opened: a code, where (path, USB/HID
// ids, socket) and what ("<action>: <why>", why being errno or library text). Returned by the
// open-time builders; the per-tick calls return LinkStatus. Printed by message() as
// "usb 0403:cb48: open USB device: no such device connected (not_connected)".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "config/base/error.hpp"

namespace kerf::firmware_host {

/// What kind of open-time failure, for a caller to branch on.
enum class TransportErrc : std::uint8_t {
    kNotConnected,  ///< no such device, or nothing listens on the socket
    kNoPermission,  ///< the device exists but this user may not open it
    kSystem,        ///< a system or library call failed (errno, libusb or hidapi text)
    kBadPath,       ///< a path empty, too long, or something else in its place
    kUnsupported,   ///< the platform or library lacks a needed feature
    kFirmware,      ///< a firmware image could not be read or loaded
    kProtocol,      ///< the device answered wrongly (a report, its identity, normal mode)
    kConfig,        ///< the profile could not be turned into an open request
};

/// Stable snake_case name ("not_connected").
inline std::string_view to_string(TransportErrc code) noexcept {
    switch (code) {
        case TransportErrc::kNotConnected:
            return "not_connected";
        case TransportErrc::kNoPermission:
            return "no_permission";
        case TransportErrc::kSystem:
            return "system";
        case TransportErrc::kBadPath:
            return "bad_path";
        case TransportErrc::kUnsupported:
            return "unsupported";
        case TransportErrc::kFirmware:
            return "firmware";
        case TransportErrc::kProtocol:
            return "protocol";
        case TransportErrc::kConfig:
            return "config";
    }
    return "unknown";
}

/// An open-time failure: code, where, what (kerf::Error).
using TransportError = Error<TransportErrc>;

/// A TransportError whose what is "<action>: <why>" (e.g. "connect: Connection refused").
inline TransportError transport_error(TransportErrc code, std::string where,
                                      std::string_view action, std::string_view why) {
    std::string what(action);
    what += ": ";
    what += why;
    return TransportError{code, std::move(where), std::move(what)};
}

}  // namespace kerf::firmware_host
