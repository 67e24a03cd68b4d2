// kerf::ipc::IpcError — why a shared-memory operation failed: a code for programs, where (the
// segment, session, journal or folder) and what differs or failed, printed by message() as
// "segment kerf.demo: header: layout version 3, expected 1 (bad_header)".
#pragma once

#include <string>
#include <string_view>

#include "config/base/error.hpp"

namespace kerf::ipc {

/// What went wrong, coarse enough for a caller to branch on.
enum class IpcErrc {
    kOsError,       ///< a system call failed (what carries errno text)
    kNotFound,      ///< no segment or journal by that name
    kInUse,         ///< a live producer already owns the segment
    kBadHeader,     ///< a header field differs from what this build expects
    kProducerGone,  ///< producer stopped or its heartbeat is stale
    kNoFreeSlot,    ///< every consumer slot is held by a live consumer
    kBadArgument,   ///< caller passed an invalid name, size or option
    kJournal,       ///< journal file missing, unreadable or corrupt
    kCorrupt,       ///< segment content failed validation
    kUntrusted,     ///< owner, mode or peer of a segment/session is not one this user may trust
};

/// Stable snake_case name of an error code ("in_use").
std::string_view to_string(IpcErrc code) noexcept;

/// An ipc failure: code, where, what (kerf::Error).
using IpcError = Error<IpcErrc>;

/// A kOsError whose what is "<what>: <strerror(errno_value)>".
IpcError os_error(std::string where, const std::string& what, int errno_value);

}  // namespace kerf::ipc
