#include "rt_core/ipc/ipc_error.hpp"

#include <cstring>
#include <utility>

namespace kerf::ipc {

std::string_view to_string(IpcErrc code) noexcept {
    switch (code) {
        case IpcErrc::kOsError:
            return "os_error";
        case IpcErrc::kNotFound:
            return "not_found";
        case IpcErrc::kInUse:
            return "in_use";
        case IpcErrc::kBadHeader:
            return "bad_header";
        case IpcErrc::kProducerGone:
            return "producer_gone";
        case IpcErrc::kNoFreeSlot:
            return "no_free_slot";
        case IpcErrc::kBadArgument:
            return "bad_argument";
        case IpcErrc::kJournal:
            return "journal";
        case IpcErrc::kCorrupt:
            return "corrupt";
        case IpcErrc::kUntrusted:
            return "untrusted";
    }
    return "unknown";
}

IpcError os_error(std::string where, const std::string& what, int errno_value) {
    return IpcError{IpcErrc::kOsError, std::move(where), what + ": " + std::strerror(errno_value)};
}

}  // namespace kerf::ipc
