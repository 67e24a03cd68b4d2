// Pins the binary layout of everything two processes (or a process and a journal file) share.
// If any of these fails, you changed the layout: bump kLayoutVersion in rt_core/ipc/layout.hpp
// and update the expected numbers here.
#include "rt_core/ipc/layout.hpp"

#include <gtest/gtest.h>

#include <cstddef>

#include "config/shm_slots.hpp"  // constants only (no link)
#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/journal_format.hpp"

namespace kerf::ipc {
namespace {

#define KERF_PIN(type, field, offset)                     \
    EXPECT_EQ(offsetof(type, field), std::size_t{offset}) \
        << #type "::" #field " moved: bump kLayoutVersion"

TEST(Layout, RecordHeaderOffsetsArePinned) {
    EXPECT_EQ(sizeof(RecordHeader), 24u);
    KERF_PIN(RecordHeader, sequence, 0);
    KERF_PIN(RecordHeader, time_ns, 8);
    KERF_PIN(RecordHeader, type, 16);
    KERF_PIN(RecordHeader, flags, 18);
    KERF_PIN(RecordHeader, checksum, 20);
}

TEST(Layout, CutPayloadOffsetsArePinned) {
    EXPECT_EQ(sizeof(CutPayload), 104u);
    KERF_PIN(CutPayload, cut_id, 0);
    KERF_PIN(CutPayload, body_id, 4);
    KERF_PIN(CutPayload, plane_point_m, 8);
    KERF_PIN(CutPayload, plane_normal, 20);
    KERF_PIN(CutPayload, seed_point_m, 32);
    KERF_PIN(CutPayload, triangle_hint, 44);
    KERF_PIN(CutPayload, blade_length_m, 48);
    KERF_PIN(CutPayload, blade_depth_m, 52);
    KERF_PIN(CutPayload, kerf_width_m, 56);
    KERF_PIN(CutPayload, swept_u_min_m, 60);
    KERF_PIN(CutPayload, swept_u_max_m, 64);
    KERF_PIN(CutPayload, swept_v_min_m, 68);
    KERF_PIN(CutPayload, swept_v_max_m, 72);
    KERF_PIN(CutPayload, feed_depth_m, 76);
    KERF_PIN(CutPayload, end_reason, 80);
    KERF_PIN(CutPayload, plane_u, 84);
    KERF_PIN(CutPayload, reserved, 96);
}

TEST(Layout, OtherEventPayloadOffsetsArePinned) {
    EXPECT_EQ(sizeof(BodyMovedPayload), 64u);
    KERF_PIN(BodyMovedPayload, body_id, 0);
    KERF_PIN(BodyMovedPayload, reserved, 4);
    KERF_PIN(BodyMovedPayload, position_m, 8);
    KERF_PIN(BodyMovedPayload, orientation_wxyz, 32);
    EXPECT_EQ(sizeof(ParametersChangedPayload), 56u);
    KERF_PIN(ParametersChangedPayload, parameter_id, 0);
    KERF_PIN(ParametersChangedPayload, reserved, 4);
    KERF_PIN(ParametersChangedPayload, value, 8);
    KERF_PIN(ParametersChangedPayload, previous_value, 16);
    KERF_PIN(ParametersChangedPayload, name, 24);
    EXPECT_EQ(sizeof(DeviceStateChangedPayload), 16u);
    KERF_PIN(DeviceStateChangedPayload, state, 0);
    KERF_PIN(DeviceStateChangedPayload, previous, 4);
    KERF_PIN(DeviceStateChangedPayload, fault_flags, 8);
    KERF_PIN(DeviceStateChangedPayload, device_index, 12);
    EXPECT_EQ(sizeof(SessionResetPayload), 16u);
    KERF_PIN(SessionResetPayload, scene_id, 0);
    KERF_PIN(SessionResetPayload, reason, 8);
    KERF_PIN(SessionResetPayload, reserved, 12);
}

TEST(Layout, EventRecordPayloadsStartAfterTheHeader) {
    EXPECT_EQ(sizeof(EventRecord), 128u);
    KERF_PIN(EventRecord, header, 0);
    KERF_PIN(EventRecord, cut, 24);
    KERF_PIN(EventRecord, body_moved, 24);
    KERF_PIN(EventRecord, parameters, 24);
    KERF_PIN(EventRecord, device, 24);
    KERF_PIN(EventRecord, reset, 24);
    KERF_PIN(EventRecord, raw, 24);
    EXPECT_EQ(static_cast<int>(EventType::kCutBegin), 1);
    EXPECT_EQ(static_cast<int>(EventType::kSessionReset), 7);
    EXPECT_EQ(static_cast<int>(EventType::kTelemetry), 100);
}

TEST(Layout, TelemetrySampleOffsetsArePinned) {
    EXPECT_EQ(sizeof(TelemetrySample), 128u);
    KERF_PIN(TelemetrySample, header, 0);
    KERF_PIN(TelemetrySample, tool_position_m, 24);
    KERF_PIN(TelemetrySample, tool_orientation_wxyz, 48);
    KERF_PIN(TelemetrySample, force_n, 64);
    KERF_PIN(TelemetrySample, contact_flags, 76);
    KERF_PIN(TelemetrySample, penetration_m, 80);
    KERF_PIN(TelemetrySample, period_ns, 84);
    KERF_PIN(TelemetrySample, compute_ns, 88);
    KERF_PIN(TelemetrySample, jitter_ns, 92);
    KERF_PIN(TelemetrySample, overrun_count, 96);
    KERF_PIN(TelemetrySample, passivity_power_w, 100);
    KERF_PIN(TelemetrySample, safety_reasons, 104);
    KERF_PIN(TelemetrySample, loop_flags, 108);
    KERF_PIN(TelemetrySample, reserved, 112);
}

TEST(Layout, LatestStateOffsetsArePinned) {
    EXPECT_EQ(sizeof(LatestState), 128u);
    KERF_PIN(LatestState, tick, 0);
    KERF_PIN(LatestState, time_ns, 8);
    KERF_PIN(LatestState, tool_position_m, 16);
    KERF_PIN(LatestState, tool_orientation_wxyz, 40);
    KERF_PIN(LatestState, force_n, 72);
    KERF_PIN(LatestState, penetration_m, 96);
    KERF_PIN(LatestState, contact_flags, 104);
    KERF_PIN(LatestState, overrun_count, 108);
    KERF_PIN(LatestState, period_ns_max, 112);
    KERF_PIN(LatestState, compute_ns_max, 116);
    KERF_PIN(LatestState, reserved, 120);
}

TEST(Layout, SegmentHeaderOffsetsArePinned) {
    EXPECT_EQ(sizeof(SegmentHeader), 256u);
    KERF_PIN(SegmentHeader, magic, 0);
    KERF_PIN(SegmentHeader, layout_version, 8);
    KERF_PIN(SegmentHeader, header_bytes, 12);
    KERF_PIN(SegmentHeader, layout_hash, 16);
    KERF_PIN(SegmentHeader, segment_bytes, 24);
    KERF_PIN(SegmentHeader, session_id, 32);
    KERF_PIN(SegmentHeader, start_time_unix_ns, 40);
    KERF_PIN(SegmentHeader, producer_pid, 48);
    KERF_PIN(SegmentHeader, slot_count, 52);
    KERF_PIN(SegmentHeader, event_capacity, 56);
    KERF_PIN(SegmentHeader, telemetry_capacity, 60);
    KERF_PIN(SegmentHeader, state, 64);
    KERF_PIN(SegmentHeader, mesh_max_bodies, 68);
    KERF_PIN(SegmentHeader, mesh_max_vertices, 72);
    KERF_PIN(SegmentHeader, mesh_max_indices, 76);
    KERF_PIN(SegmentHeader, journal_path, 80);
    KERF_PIN(SegmentHeader, reserved, 208);
    EXPECT_EQ(kMagic, 0x314D48534652454Bull);
    EXPECT_EQ(kLayoutVersion, 3u);
}

TEST(Layout, ProducerAndSlotControlLinesArePinned) {
    EXPECT_EQ(sizeof(ProducerStatus), 64u);
    KERF_PIN(ProducerStatus, heartbeat_tick, 0);
    KERF_PIN(ProducerStatus, heartbeat_ns, 8);
    KERF_PIN(ProducerStatus, next_event_sequence, 16);
    KERF_PIN(ProducerStatus, telemetry_dropped, 24);
    KERF_PIN(ProducerStatus, events_dropped, 32);
    EXPECT_EQ(sizeof(SlotControl), 64u);
    KERF_PIN(SlotControl, claim_word, 0);
    KERF_PIN(SlotControl, heartbeat_ns, 8);
    KERF_PIN(SlotControl, consumer_pid, 16);
    KERF_PIN(SlotControl, flags, 20);
    KERF_PIN(SlotControl, rejected_count, 24);
    KERF_PIN(SlotControl, delivered, 32);
}

TEST(Layout, RingIndicesSitOnSeparate64ByteLines) {
    EXPECT_EQ(sizeof(RingControl), 256u);
    KERF_PIN(RingControl, write_index, 0);
    KERF_PIN(RingControl, read_index, 64);
    KERF_PIN(RingControl, pushed_count, 128);
    KERF_PIN(RingControl, dropped_count, 192);
    EXPECT_EQ(sizeof(ConsumerSlot), 64u + 512u + 128u * (kEventCapacity + kTelemetryCapacity));
    KERF_PIN(ConsumerSlot, control, 0);
    KERF_PIN(ConsumerSlot, event_ring, 64);
    KERF_PIN(ConsumerSlot, telemetry_ring, 320);
    KERF_PIN(ConsumerSlot, events, 576);
    KERF_PIN(ConsumerSlot, telemetry, 576 + 128 * kEventCapacity);
}

TEST(Layout, SegmentSectionsArePinned) {
    KERF_PIN(SegmentLayout, header, 0);
    KERF_PIN(SegmentLayout, producer, 256);
    KERF_PIN(SegmentLayout, journal_next_sequence, 320);
    KERF_PIN(SegmentLayout, journal_dropped, 384);
    KERF_PIN(SegmentLayout, state, 448);
    KERF_PIN(SegmentLayout, slots, 640);
    KERF_PIN(SegmentLayout, mailbox, 640 + 4 * (576 + 128 * (4096 + 2048)));
    EXPECT_EQ(sizeof(SeqlockCell<LatestState>), 192u);
    EXPECT_EQ(kSlotCount, 4u);
    EXPECT_EQ(kEventCapacity, 4096u);
    EXPECT_EQ(kTelemetryCapacity, 2048u);
}

// kerf.toml's [shm] consumer_slots is checked against these (issue 9, item 6): the config's idea
// of the segment's slots and of the reserved ones must be the layout's.
TEST(Layout, TheConfigKnowsTheSegmentsSlotsAndTheReservedOnes) {
    EXPECT_EQ(config::kSegmentConsumerSlots, kSlotCount);
    EXPECT_EQ(config::kReservedConsumerSlots, kFirstToolSlot);
    EXPECT_LT(kDisplaySlot, kFirstToolSlot);
    EXPECT_LT(kMonitorSlot, kFirstToolSlot);
}

TEST(Layout, MeshMailboxOffsetsArePinned) {
    EXPECT_EQ(sizeof(MeshBodyEntry), 80u);
    KERF_PIN(MeshBodyEntry, vertex_offset, 0);
    KERF_PIN(MeshBodyEntry, vertex_count, 4);
    KERF_PIN(MeshBodyEntry, index_offset, 8);
    KERF_PIN(MeshBodyEntry, index_count, 12);
    KERF_PIN(MeshBodyEntry, world_from_body, 16);
    KERF_PIN(MeshBufferHeader, generation, 0);
    KERF_PIN(MeshBufferHeader, body_count, 8);
    KERF_PIN(MeshBufferHeader, vertex_count, 12);
    KERF_PIN(MeshBufferHeader, index_count, 16);
    KERF_PIN(MeshBufferHeader, reserved, 20);
    KERF_PIN(MeshBufferHeader, content_hash, 24);
    KERF_PIN(MeshBufferHeader, bodies, 32);
    KERF_PIN(MeshBuffer, sequence, 0);
    KERF_PIN(MeshBuffer, header, 64);
    KERF_PIN(MeshBuffer, vertices_m, 64 + 32 + 80 * 64);
    KERF_PIN(MeshBuffer, indices, 64 + 32 + 80 * 64 + 12 * (1 << 20));
    KERF_PIN(MeshBuffer, materials, 64 + 32 + 80 * 64 + 12 * (1 << 20) + 12 * (1 << 21));
    EXPECT_EQ(sizeof(MeshBuffer), 39851136u);
    KERF_PIN(MeshMailbox, latest, 0);
    KERF_PIN(MeshMailbox, buffers, 64);
}

TEST(Layout, JournalFileHeaderOffsetsArePinned) {
    EXPECT_EQ(sizeof(JournalFileHeader), 64u);
    KERF_PIN(JournalFileHeader, magic, 0);
    KERF_PIN(JournalFileHeader, version, 8);
    KERF_PIN(JournalFileHeader, record_bytes, 12);
    KERF_PIN(JournalFileHeader, session_id, 16);
    KERF_PIN(JournalFileHeader, layout_hash, 24);
    KERF_PIN(JournalFileHeader, start_time_unix_ns, 32);
    KERF_PIN(JournalFileHeader, reserved, 40);
}

TEST(Layout, LayoutHashIsStableForThisVersion) {
    // Printed so a reviewer sees it change; any layout change changes it.
    std::printf("layout hash 0x%016llx, segment %zu bytes\n",
                static_cast<unsigned long long>(kLayoutHash), sizeof(SegmentLayout));
    EXPECT_NE(kLayoutHash, 0u);
    EXPECT_EQ(sizeof(SegmentLayout) % 64, 0u);
}

}  // namespace
}  // namespace kerf::ipc
