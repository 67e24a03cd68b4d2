// kerf::ipc::IpcError — why a shared-memory operation failed: a code for programs and a message
// for people that names what and where ("segment /kerf.demo: header: layout version 3, expected
// 1").
#pragma once

#include <string>

namespace kerf::ipc {

/// What went wrong, coarse enough for a caller to branch on.
enum class IpcErrc {
    kOsError,       ///< a system call failed (message carries errno text)
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

/// Stable lower-case name of an error code ("in_use").
const char* to_string(IpcErrc code) noexcept;

/// An error value: a code plus a human sentence saying what differs or failed, and where.
struct IpcError {
    IpcErrc code = IpcErrc::kOsError;
    std::string message;
};

/// Builds an IpcError from a code and message; for the `return Err{make_error(...)}` idiom.
IpcError make_error(IpcErrc code, std::string message);

/// Builds a kOsError whose message is "<what>: <strerror(errno_value)>".
IpcError os_error(const std::string& what, int errno_value);

}  // namespace kerf::ipc
