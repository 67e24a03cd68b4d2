// The event contract (kerf::ipc records, float, shared memory) turned into CutSession calls
// (double, kerf::cut types). The one place kerf-display and the tests decode events, so both
// apply exactly the same edits.
//
//   ipc::EventRecord record;
//   while (consumer.try_next(record) == ipc::Poll::kEvent) apply_record(session, record);
#pragma once

#include "display/cut/cut_session.hpp"
#include "rt_core/ipc/records.hpp"

namespace kerf::display {

/// What applying one record did.
struct RecordOutcome {
    cut::ApplyReport report;     ///< the session's answer (kIgnored for types it does not use)
    bool session_reset = false;  ///< kSessionReset: the caller rebuilds the session from the scene
    bool topology = false;       ///< a cut event (begin / progress / end) was applied
};

/// Applies one validated record (ipc::Consumer validated type, checksum, finiteness) to
/// `session`. Cut events, BodyMoved and SessionReset act; other types are ignored.
RecordOutcome apply_record(cut::CutSession& session, const ipc::EventRecord& record);

/// The session's events for one record, for tools and tests that build records themselves.
cut::CutBegin to_cut_begin(const ipc::CutPayload& cut);
cut::CutProgress to_cut_progress(const ipc::CutPayload& cut);
cut::BodyMoved to_body_moved(const ipc::BodyMovedPayload& moved);

/// Blade size written into encoded cut records (the session does not use it), m.
inline constexpr double kRecordBladeLength_m = 0.025;
inline constexpr double kRecordBladeDepth_m = 0.010;

/// Encodes session events as records (type and payload; the producer stamps sequence, time and
/// checksum). Progress and end carry their cut's begin too, as every cut record does.
ipc::EventRecord make_record(const cut::CutBegin& begin);
ipc::EventRecord make_record(const cut::CutProgress& progress, const cut::CutBegin& of_cut);
ipc::EventRecord make_record(const cut::CutEnd& end, const cut::CutBegin& of_cut);
ipc::EventRecord make_record(const cut::BodyMoved& moved);

}  // namespace kerf::display
