// The session journal file: a 64-byte header, then EventRecords (128 bytes each) in increasing
// sequence order, appended by the producer's journal thread. Sequence numbers are contiguous
// unless the journal thread fell behind (counted in SegmentLayout::journal_dropped). The journal
// doubles as the session recording for replay.
#pragma once

#include <cstdint>

#include "rt_core/ipc/records.hpp"

namespace kerf::ipc {

inline constexpr std::uint64_t kJournalMagic = 0x314E524A4652454Bull;  ///< "KERFJRN1"
inline constexpr std::uint32_t kJournalVersion = 1;

struct JournalFileHeader {
    std::uint64_t magic;               ///< kJournalMagic
    std::uint32_t version;             ///< kJournalVersion
    std::uint32_t record_bytes;        ///< sizeof(EventRecord)
    std::uint64_t session_id;          ///< the segment header's session id
    std::uint64_t layout_hash;         ///< kLayoutHash of the writer
    std::uint64_t start_time_unix_ns;  ///< the segment's start time, ns
    std::uint8_t reserved[24];         ///< 0
};
static_assert(sizeof(JournalFileHeader) == 64);

}  // namespace kerf::ipc
