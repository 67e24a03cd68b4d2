// `kerf shm ls|tail|stats`: inspect live Kerf sessions. Sessions are found through their sockets in
// the runtime folder (see rt_core/ipc/session_socket.hpp); each segment is received from its
// producer over that socket, so every name works and no file in /dev/shm is involved.
//   ls     sessions with producer pid, health, heartbeat age and consumers; stale sockets of dead
//          sessions are reported and removed
//   tail   attach as a consumer and print events as they come (journal first with --from)
//   stats  per-slot lag, drops and rejections, producer and journal counters
//   rm     removes the sockets of dead sessions (named, or all); refuses a live one
// Read-only except `tail`, which claims a consumer slot like any other consumer. --json output is
// one JSON document (ls, stats) or one per line (tail) on stdout; logs go to stderr.
#include <chrono>
#include <cinttypes>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/session_socket.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/safe_text.hpp"
#include "tools/kerf/session_files.hpp"

namespace kerf::cli {
namespace {

using namespace kerf::ipc;
using nlohmann::json;

[[noreturn]] void fail(std::string_view command, std::string_view what, std::string_view why) {
    std::cerr << "kerf shm " << command << ": " << what << ": " << safe_text(why) << "\n";
    throw CLI::RuntimeError(kExitFailure);
}

double age_ms(std::uint64_t then_ns) {
    const auto now = monotonic_ns();
    return then_ns == 0 || then_ns > now ? -1.0 : double(now - then_ns) / 1e6;
}

struct SlotView {
    std::uint32_t index;
    std::int32_t pid;
    bool alive;
    std::uint64_t event_lag, event_dropped, telemetry_lag, telemetry_dropped, delivered, rejected;
};

std::vector<SlotView> active_slots(const SegmentLayout& s) {
    std::vector<SlotView> out;
    for (std::uint32_t i = 0; i < kSlotCount; ++i) {
        const ConsumerSlot& slot = s.slots[i];
        const auto word = slot.control.claim_word.load(std::memory_order_acquire);
        if ((word & 3u) != std::uint64_t(SlotState::kActive)) continue;
        auto lag = [](const RingControl& r) {
            const auto w = r.write_index.value.load(std::memory_order_acquire);
            const auto rd = r.read_index.value.load(std::memory_order_acquire);
            return w >= rd ? w - rd : 0;
        };
        out.push_back({i, claim_pid(word), !slot_holder_gone(slot.control), lag(slot.event_ring),
                       slot.event_ring.dropped_count.value.load(), lag(slot.telemetry_ring),
                       slot.telemetry_ring.dropped_count.value.load(),
                       slot.control.delivered.load(), slot.control.rejected_count.load()});
    }
    return out;
}

std::string hex16(std::uint64_t v) {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
    return buf;
}

void run_ls(bool json_out) {
    const std::string runtime = default_runtime_dir();
    json sessions = json::array();
    int shown = 0;
    for (const SessionEntry& entry : list_session_dirs(runtime)) {
        if (!entry.has_socket) continue;  // a finished session: only its journals are left
        const std::string name = safe_text(entry.name);
        auto seg = SegmentBuilder().name(entry.name).open();
        json row = {{"name", name}};
        ++shown;
        if (!seg && seg.error().code == IpcErrc::kProducerGone) {
            const bool removed = remove_stale_socket(runtime, entry.name);
            row["error"] = "stale";
            row["removed"] = removed;
            if (!json_out) {
                std::printf("%s  stale: its producer died (socket %s)\n", name.c_str(),
                            removed ? "removed" : "left: not ours");
            }
            sessions.push_back(row);
            continue;
        }
        if (!seg) {
            row["error"] = to_string(seg.error().code);
            row["message"] = safe_text(seg.error().message());
            if (!json_out) {
                std::printf("%s  refused: %s\n", name.c_str(),
                            safe_text(seg.error().message()).c_str());
            }
            sessions.push_back(row);
            continue;
        }
        const SegmentLayout& s = seg->layout();
        const auto slots = active_slots(s);
        const std::string health(to_string(producer_health(s)));
        const double beat = age_ms(s.producer.heartbeat_ns.load());
        row["session_id"] = hex16(s.header.session_id);
        row["producer_pid"] = s.header.producer_pid;
        row["health"] = health;
        row["heartbeat_age_ms"] = beat;
        row["events"] = s.producer.next_event_sequence.load();
        row["consumers"] = slots.size();
        sessions.push_back(row);
        if (json_out) continue;
        std::printf("%s  session %016" PRIx64
                    "  producer pid %d %s  heartbeat %.1f ms ago  "
                    "events %" PRIu64 "  consumers %zu:",
                    name.c_str(), s.header.session_id, s.header.producer_pid, health.c_str(), beat,
                    s.producer.next_event_sequence.load(), slots.size());
        for (const auto& v : slots)
            std::printf(" [slot %u pid %d%s]", v.index, v.pid, v.alive ? "" : " dead");
        std::printf("\n");
    }
    if (json_out) {
        std::cout << sessions.dump(2) << "\n";
    } else if (shown == 0) {
        std::cout << "no Kerf sessions in " << safe_text(runtime) << "\n";
    }
    std::cout.flush();
}

void run_stats(const std::string& name, bool json_out) {
    auto seg = SegmentBuilder().name(name).open();
    if (!seg) fail("stats", "cannot open segment", seg.error().message());
    const SegmentLayout& s = seg->layout();
    const auto slots = active_slots(s);
    const ProducerStatus& p = s.producer;
    const std::string journal = safe_field(s.header.journal_path, sizeof s.header.journal_path);
    if (json_out) {
        json doc = {{"name", safe_text(name)},
                    {"health", to_string(producer_health(s))},
                    {"heartbeat_age_ms", age_ms(p.heartbeat_ns.load())},
                    {"tick", p.heartbeat_tick.load()},
                    {"events", p.next_event_sequence.load()},
                    {"journal", journal},
                    {"journal_next", s.journal_next_sequence.value.load()},
                    {"journal_dropped", s.journal_dropped.value.load()},
                    {"events_dropped", p.events_dropped.load()},
                    {"telemetry_dropped", p.telemetry_dropped.load()},
                    {"mesh_latest", s.mailbox.latest.value.load() >> 1},
                    {"slots", json::array()}};
        for (const auto& v : slots) {
            doc["slots"].push_back({{"slot", v.index},
                                    {"pid", v.pid},
                                    {"alive", v.alive},
                                    {"event_lag", v.event_lag},
                                    {"event_dropped", v.event_dropped},
                                    {"telemetry_lag", v.telemetry_lag},
                                    {"telemetry_dropped", v.telemetry_dropped},
                                    {"delivered", v.delivered},
                                    {"rejected", v.rejected}});
        }
        std::cout << doc.dump(2) << "\n";
        return;
    }
    std::printf("%s: producer pid %d %s, heartbeat tick %" PRIu64 " %.1f ms ago\n",
                safe_text(name).c_str(), s.header.producer_pid,
                std::string(to_string(producer_health(s))).c_str(), p.heartbeat_tick.load(),
                age_ms(p.heartbeat_ns.load()));
    std::printf("events %" PRIu64 ", journal up to %" PRIu64 " (%s), journal dropped %" PRIu64
                ", ring drops %" PRIu64 " events %" PRIu64 " telemetry\n",
                p.next_event_sequence.load(), s.journal_next_sequence.value.load(), journal.c_str(),
                s.journal_dropped.value.load(), p.events_dropped.load(),
                p.telemetry_dropped.load());
    std::printf(
        "slot  pid       alive  event lag  event drops  telem lag  telem drops  delivered  "
        "rejected\n");
    for (const auto& v : slots) {
        std::printf("%-5u %-9d %-6s %-10" PRIu64 " %-12" PRIu64 " %-10" PRIu64 " %-12" PRIu64
                    " %-10" PRIu64 " %" PRIu64 "\n",
                    v.index, v.pid, v.alive ? "yes" : "no", v.event_lag, v.event_dropped,
                    v.telemetry_lag, v.telemetry_dropped, v.delivered, v.rejected);
    }
}

json event_json(const EventRecord& r) {
    json j = {{"sequence", r.header.sequence},
              {"time_ns", r.header.time_ns},
              {"type", to_string(r.header.type)}};
    switch (r.header.type) {
        case EventType::kCutBegin:
        case EventType::kCutProgress:
        case EventType::kCutEnd: {
            const CutPayload& c = r.cut;
            j["cut_id"] = c.cut_id;
            j["body_id"] = c.body_id;
            j["plane_point_m"] = {c.plane_point_m[0], c.plane_point_m[1], c.plane_point_m[2]};
            j["plane_normal"] = {c.plane_normal[0], c.plane_normal[1], c.plane_normal[2]};
            j["feed_depth_m"] = c.feed_depth_m;
            break;
        }
        case EventType::kBodyMoved:
            j["body_id"] = r.body_moved.body_id;
            j["position_m"] = {r.body_moved.position_m[0], r.body_moved.position_m[1],
                               r.body_moved.position_m[2]};
            break;
        case EventType::kParametersChanged:
            j["name"] = safe_field(r.parameters.name, sizeof r.parameters.name);
            j["value"] = r.parameters.value;
            j["previous"] = r.parameters.previous_value;
            break;
        case EventType::kDeviceStateChanged:
            j["state"] = to_string(r.device.state);
            j["previous"] = to_string(r.device.previous);
            j["fault_flags"] = r.device.fault_flags;
            break;
        default:
            j["scene_id"] = r.reset.scene_id;
    }
    return j;
}

void print_event(const EventRecord& r, bool json_out) {
    if (json_out) {
        std::cout << event_json(r).dump() << "\n" << std::flush;
        return;
    }
    std::printf("%-8" PRIu64 " %-14.6f %-20s", r.header.sequence, double(r.header.time_ns) / 1e9,
                std::string(to_string(r.header.type)).c_str());
    switch (r.header.type) {
        case EventType::kCutBegin:
        case EventType::kCutProgress:
        case EventType::kCutEnd: {
            const CutPayload& c = r.cut;
            std::printf("cut %u body %u point (%g %g %g) m normal (%g %g %g) feed %g m\n", c.cut_id,
                        c.body_id, c.plane_point_m[0], c.plane_point_m[1], c.plane_point_m[2],
                        c.plane_normal[0], c.plane_normal[1], c.plane_normal[2], c.feed_depth_m);
            break;
        }
        case EventType::kBodyMoved:
            std::printf("body %u position (%g %g %g) m\n", r.body_moved.body_id,
                        r.body_moved.position_m[0], r.body_moved.position_m[1],
                        r.body_moved.position_m[2]);
            break;
        case EventType::kParametersChanged:
            std::printf("%s = %g (was %g)\n",
                        safe_field(r.parameters.name, sizeof r.parameters.name).c_str(),
                        r.parameters.value, r.parameters.previous_value);
            break;
        case EventType::kDeviceStateChanged:
            std::printf("%s (was %s) faults 0x%x\n", std::string(to_string(r.device.state)).c_str(),
                        std::string(to_string(r.device.previous)).c_str(), r.device.fault_flags);
            break;
        default:
            std::printf("scene %" PRIu64 "\n", r.reset.scene_id);
    }
    std::fflush(stdout);
}

void run_tail(const std::string& name, std::optional<std::uint64_t> from, std::uint64_t count,
              bool json_out) {
    auto c = ConsumerBuilder()
                 .segment_name(name)
                 .from_sequence(from ? *from : ConsumerBuilder::kFromNow)
                 .attach();
    if (!c) fail("tail", "cannot attach to segment", c.error().message());
    std::signal(SIGINT, [](int) { std::_Exit(0); });  // the slot is reclaimed once we are gone
    EventRecord r;
    std::uint64_t printed = 0;
    while (count == 0 || printed < count) {
        if (c->try_next(r) == Poll::kEvent) {
            print_event(r, json_out);
            ++printed;
            continue;
        }
        const ProducerHealth h = c->producer_health();
        if (h == ProducerHealth::kStopped) return;
        if (h == ProducerHealth::kDead) fail("tail", "segment " + name, "producer died");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

/// `kerf shm rm [NAME...]`: the named sessions' sockets if their producer is gone (every dead
/// session's when none is named). A live session, or one that is not there, is an error.
void run_rm(const std::vector<std::string>& names) {
    if (names.empty()) {
        const auto removed = remove_stale_sessions();
        for (const auto& n : removed)
            std::printf("removed %s (its producer died)\n", safe_text(n).c_str());
        if (removed.empty()) std::printf("no dead sessions\n");
        return;
    }
    const std::string runtime = default_runtime_dir();
    bool failed = false;
    for (const std::string& name : names) {
        if (remove_stale_socket(runtime, name)) {
            std::printf("removed %s (its producer died)\n", safe_text(name).c_str());
            continue;
        }
        auto seg = SegmentBuilder().name(name).open();
        std::fprintf(stderr, "kerf shm rm: %s: %s\n", safe_text(name).c_str(),
                     seg ? "live (its kerf-rt is running: stop it instead)"
                         : safe_text(seg.error().message()).c_str());
        failed = true;
    }
    if (failed) throw CLI::RuntimeError(kExitFailure);
}

}  // namespace

void add_shm_commands(CLI::App& app) {
    CLI::App* shm = app.add_subcommand("shm", "inspect Kerf shared-memory sessions");
    shm->require_subcommand(1);
    struct Options {
        std::string name;
        std::optional<std::uint64_t> from;
        std::uint64_t count = 0;
        bool json = false;
    };
    auto o = std::make_shared<Options>();

    CLI::App* ls = shm->add_subcommand("ls", "list sessions: producer, heartbeat age, consumers");
    ls->add_flag("--json", o->json, "machine-readable output (one JSON array)");
    ls->callback([o] { run_ls(o->json); });

    CLI::App* tail = shm->add_subcommand("tail", "print events live (as a consumer)");
    tail->add_option("name", o->name, "session name, e.g. kerf.demo")->required();
    tail->add_option("--from", o->from, "replay from this sequence (journal), then follow");
    tail->add_option("--count", o->count, "stop after this many events (0: until stopped)");
    tail->add_flag("--json", o->json, "one JSON object per event, one per line");
    tail->callback([o] { run_tail(o->name, o->from, o->count, o->json); });

    CLI::App* rm = shm->add_subcommand(
        "rm", "remove what dead sessions left (their sockets); a live session is refused");
    auto rm_names = std::make_shared<std::vector<std::string>>();
    rm->add_option("names", *rm_names, "session names (default: every dead session)");
    rm->callback([rm_names] { run_rm(*rm_names); });

    CLI::App* stats = shm->add_subcommand("stats", "per-consumer lag, drops and rejections");
    stats->add_option("name", o->name, "session name, e.g. kerf.demo")->required();
    stats->add_flag("--json", o->json, "machine-readable output (one JSON object)");
    stats->callback([o] { run_stats(o->name, o->json); });
}

}  // namespace kerf::cli
