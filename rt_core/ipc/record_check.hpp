// Integrity of records read from shared memory or the journal: a checksum the producer stamps and
// a validator that rejects anything a well-behaved producer could not have written.
#pragma once

#include <cstdint>
#include <string_view>

#include "rt_core/ipc/records.hpp"

namespace kerf::ipc {

/// Why a record was rejected.
enum class RecordFault : std::uint8_t {
    kNone,
    kBadType,      ///< type tag is not a known EventType (or wrong kind for this ring)
    kBadChecksum,  ///< bytes changed after the producer stamped the record
    kNotFinite,    ///< a float field is NaN or infinite
    kOutOfRange,   ///< an enum, unit vector, size or name is out of its range
};
std::string_view to_string(RecordFault fault) noexcept;

/// 32-bit checksum of a 128-byte record, computed with header.checksum taken as 0. ~10 ns.
/// noexcept, allocation-free: safe on the real-time thread.
std::uint32_t record_checksum(const void* record_128_bytes) noexcept;

/// Stamps header.checksum. noexcept, real-time safe.
void stamp_checksum(EventRecord& record) noexcept;
void stamp_checksum(TelemetrySample& sample) noexcept;

/// Checks type tag, checksum, finiteness and ranges of an event read from untrusted memory.
RecordFault validate_event(const EventRecord& record) noexcept;

/// Checks type tag, checksum and finiteness of a telemetry sample.
RecordFault validate_telemetry(const TelemetrySample& sample) noexcept;

/// Checks finiteness of a LatestState read through the seqlock.
RecordFault validate_state(const LatestState& state) noexcept;

}  // namespace kerf::ipc
