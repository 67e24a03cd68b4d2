#include "display/app/session_events_ipc.hpp"

#include <cstring>

namespace kerf::display {
namespace {

cut::Vec3 vec(const float (&v)[3]) { return cut::Vec3(v[0], v[1], v[2]); }

void put(float (&out)[3], const cut::Vec3& v) {
    for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(v[i]);
}

cut::BladeFrame blade(const ipc::CutPayload& c) {
    return cut::BladeFrame{vec(c.plane_point_m), vec(c.plane_normal), vec(c.plane_u)};
}

ipc::EventRecord empty_record(ipc::EventType type) {
    ipc::EventRecord r;
    std::memset(&r, 0, sizeof r);
    r.header.type = type;
    return r;
}

void put_blade(ipc::CutPayload& c, const cut::BladeFrame& b) {
    put(c.plane_point_m, b.point_m);
    put(c.plane_normal, b.normal);
    put(c.plane_u, b.u);
}

}  // namespace

cut::CutBegin to_cut_begin(const ipc::CutPayload& c) {
    cut::CutBegin b;
    b.cut_id = c.cut_id;
    b.body_id = c.body_id;
    b.blade = blade(c);
    b.seed_m = vec(c.seed_point_m);
    b.triangle_hint = c.triangle_hint == ipc::kNoTriangle ? -1 : std::int64_t{c.triangle_hint};
    b.kerf_width_m = c.kerf_width_m;
    return b;
}

cut::CutProgress to_cut_progress(const ipc::CutPayload& c) {
    return cut::CutProgress{
        c.cut_id, blade(c), {c.swept_u_min_m, c.swept_u_max_m, c.swept_v_min_m, c.swept_v_max_m}};
}

cut::BodyMoved to_body_moved(const ipc::BodyMovedPayload& m) {
    cut::BodyMoved b;
    b.body_id = m.body_id;
    b.pose.position_m = cut::Vec3(m.position_m[0], m.position_m[1], m.position_m[2]);
    for (int i = 0; i < 4; ++i)
        b.pose.orientation_wxyz[static_cast<std::size_t>(i)] = m.orientation_wxyz[i];
    return b;
}

RecordOutcome apply_record(cut::CutSession& session, const ipc::EventRecord& r) {
    RecordOutcome out;
    switch (r.header.type) {
        case ipc::EventType::kCutBegin:
            out.report = session.begin(to_cut_begin(r.cut));
            out.topology = true;
            break;
        case ipc::EventType::kCutProgress:
            out.report = session.progress(to_cut_progress(r.cut));
            out.topology = true;
            break;
        case ipc::EventType::kCutEnd: {
            const auto kind =
                r.cut.end_reason == ipc::CutEndReason::kCompleted   ? cut::CutEndKind::kCompleted
                : r.cut.end_reason == ipc::CutEndReason::kWithdrawn ? cut::CutEndKind::kWithdrawn
                                                                    : cut::CutEndKind::kAborted;
            out.report = session.end({r.cut.cut_id, kind});
            out.topology = true;
            break;
        }
        case ipc::EventType::kBodyMoved:
            out.report = session.move_body(to_body_moved(r.body_moved));
            break;
        case ipc::EventType::kSessionReset:
            out.session_reset = true;
            out.report.outcome = cut::EventOutcome::kApplied;
            break;
        default:
            out.report.why = "not an event the display uses";
            break;
    }
    out.topology = out.topology && out.report.outcome == cut::EventOutcome::kApplied;
    return out;
}

ipc::EventRecord make_record(const cut::CutBegin& b) {
    ipc::EventRecord r = empty_record(ipc::EventType::kCutBegin);
    r.cut.cut_id = b.cut_id;
    r.cut.body_id = b.body_id;
    put_blade(r.cut, b.blade);
    put(r.cut.seed_point_m, b.seed_m);
    r.cut.triangle_hint =
        b.triangle_hint < 0 ? ipc::kNoTriangle : static_cast<std::uint32_t>(b.triangle_hint);
    r.cut.kerf_width_m = static_cast<float>(b.kerf_width_m);
    r.cut.blade_length_m = static_cast<float>(kRecordBladeLength_m);
    r.cut.blade_depth_m = static_cast<float>(kRecordBladeDepth_m);
    return r;
}

ipc::EventRecord make_record(const cut::CutProgress& p, const cut::CutBegin& of_cut) {
    ipc::EventRecord r = make_record(of_cut);
    r.header.type = ipc::EventType::kCutProgress;
    r.cut.cut_id = p.cut_id;
    put_blade(r.cut, p.blade);
    r.cut.swept_u_min_m = static_cast<float>(p.swept.u_min_m);
    r.cut.swept_u_max_m = static_cast<float>(p.swept.u_max_m);
    r.cut.swept_v_min_m = static_cast<float>(p.swept.v_min_m);
    r.cut.swept_v_max_m = static_cast<float>(p.swept.v_max_m);
    return r;
}

ipc::EventRecord make_record(const cut::CutEnd& e, const cut::CutBegin& of_cut) {
    ipc::EventRecord r = make_record(of_cut);
    r.header.type = ipc::EventType::kCutEnd;
    r.cut.cut_id = e.cut_id;
    r.cut.end_reason = e.kind == cut::CutEndKind::kCompleted   ? ipc::CutEndReason::kCompleted
                       : e.kind == cut::CutEndKind::kWithdrawn ? ipc::CutEndReason::kWithdrawn
                                                               : ipc::CutEndReason::kAborted;
    return r;
}

ipc::EventRecord make_record(const cut::BodyMoved& m) {
    ipc::EventRecord r = empty_record(ipc::EventType::kBodyMoved);
    r.body_moved.body_id = m.body_id;
    for (int i = 0; i < 3; ++i) r.body_moved.position_m[i] = m.pose.position_m[i];
    for (int i = 0; i < 4; ++i)
        r.body_moved.orientation_wxyz[i] = m.pose.orientation_wxyz[static_cast<std::size_t>(i)];
    return r;
}

}  // namespace kerf::display
