#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host {

std::string_view to_string(LinkStatus status) noexcept {
    switch (status) {
        case LinkStatus::kOk:
            return "ok";
        case LinkStatus::kTimeout:
            return "timed out";
        case LinkStatus::kBusy:
            return "previous transfer still in flight";
        case LinkStatus::kStall:
            return "device refused the request (stall)";
        case LinkStatus::kDisconnected:
            return "device disconnected";
        case LinkStatus::kOverflow:
            return "device sent more than the buffer holds";
        case LinkStatus::kError:
            return "I/O error";
    }
    return "unknown link status";
}

}  // namespace kerf::firmware_host
