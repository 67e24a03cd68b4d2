// TransportError — why a transport could not be opened: what, where (path / ids), why (errno
// or library message). Returned by the open-time builders; the per-tick calls return LinkStatus.
#pragma once

#include <string>

namespace kerf::firmware_host {

struct TransportError {
    std::string what;   ///< e.g. "connect to emulator socket"
    std::string where;  ///< e.g. "/run/user/1000/kerf-hapsim.sock" or "usb 0403:cb48"
    std::string why;    ///< e.g. "No such file or directory"
    std::string message() const { return what + ": " + where + ": " + why; }
};

}  // namespace kerf::firmware_host
