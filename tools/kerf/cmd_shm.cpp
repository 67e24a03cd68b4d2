// `kerf shm ls|tail|stats`: inspect live Kerf session segments (POSIX shared memory in /dev/shm).
//   ls     sessions with producer pid, health, heartbeat age and consumers
//   tail   attach as a consumer and print events as they come (journal first with --from)
//   stats  per-slot lag, drops and rejections, producer and journal counters
// Read-only except `tail`, which claims a consumer slot like any other consumer.
#include <dirent.h>

#include <chrono>
#include <cinttypes>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "tools/kerf/commands.hpp"

namespace kerf::cli {
namespace {

using namespace kerf::ipc;

[[noreturn]] void fail(std::string_view command, std::string_view what, std::string_view why) {
    std::cerr << "kerf shm " << command << ": " << what << ": " << why << "\n";
    throw CLI::RuntimeError(kExitFailure);
}

double age_ms(std::uint64_t then_ns) {
    const auto now = monotonic_ns();
    return then_ns == 0 || then_ns > now ? -1.0 : double(now - then_ns) / 1e6;
}

std::vector<std::string> segment_names() {
    std::vector<std::string> out;
    DIR* d = opendir("/dev/shm");
    if (d == nullptr) return out;
    while (dirent* e = readdir(d)) {
        const std::string n = e->d_name;
        if (n.rfind("kerf.", 0) == 0 && n.find(".kjournal") == std::string::npos) out.push_back(n);
    }
    closedir(d);
    std::sort(out.begin(), out.end());
    return out;
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

void run_ls(bool json) {
    const auto names = segment_names();
    if (json) std::cout << "[";
    bool first = true;
    for (const auto& name : names) {
        auto seg = SegmentBuilder().name(name).open();
        if (json) std::cout << (first ? "" : ",") << "\n  {\"name\": \"" << name << "\"";
        first = false;
        if (!seg) {
            if (json)
                std::cout << ", \"error\": \"" << to_string(seg.error().code) << "\"}";
            else
                std::cout << name << "  unreadable: " << seg.error().message << "\n";
            continue;
        }
        const SegmentLayout& s = seg->layout();
        const auto slots = active_slots(s);
        const char* health = to_string(producer_health(s));
        const double beat = age_ms(s.producer.heartbeat_ns.load());
        if (json) {
            std::printf(", \"session_id\": \"%016" PRIx64
                        "\", \"producer_pid\": %d, \"health\": "
                        "\"%s\", \"heartbeat_age_ms\": %.1f, \"consumers\": %zu}",
                        s.header.session_id, s.header.producer_pid, health, beat, slots.size());
            std::fflush(stdout);
            continue;
        }
        std::printf("%s  session %016" PRIx64
                    "  producer pid %d %s  heartbeat %.1f ms ago  "
                    "events %" PRIu64 "  consumers %zu:",
                    name.c_str(), s.header.session_id, s.header.producer_pid, health, beat,
                    s.producer.next_event_sequence.load(), slots.size());
        for (const auto& v : slots)
            std::printf(" [slot %u pid %d%s]", v.index, v.pid, v.alive ? "" : " dead");
        std::printf("\n");
    }
    if (json)
        std::cout << (names.empty() ? "]\n" : "\n]\n");
    else if (names.empty())
        std::cout << "no Kerf sessions in /dev/shm\n";
    std::cout.flush();
}

void run_stats(const std::string& name, bool json) {
    auto seg = SegmentBuilder().name(name).open();
    if (!seg) fail("stats", "cannot open segment", seg.error().message);
    const SegmentLayout& s = seg->layout();
    const auto slots = active_slots(s);
    const ProducerStatus& p = s.producer;
    if (json) {
        std::printf(
            "{\"name\": \"%s\", \"health\": \"%s\", \"heartbeat_age_ms\": %.1f, "
            "\"tick\": %" PRIu64 ", \"events\": %" PRIu64 ", \"journal_next\": %" PRIu64
            ", \"journal_dropped\": %" PRIu64 ", \"events_dropped\": %" PRIu64
            ", \"telemetry_dropped\": %" PRIu64 ", \"mesh_latest\": %" PRIu64 ", \"slots\": [",
            name.c_str(), to_string(producer_health(s)), age_ms(p.heartbeat_ns.load()),
            p.heartbeat_tick.load(), p.next_event_sequence.load(),
            s.journal_next_sequence.value.load(), s.journal_dropped.value.load(),
            p.events_dropped.load(), p.telemetry_dropped.load(),
            s.mailbox.latest.value.load() >> 1);
        for (std::size_t i = 0; i < slots.size(); ++i) {
            const auto& v = slots[i];
            std::printf("%s{\"slot\": %u, \"pid\": %d, \"alive\": %s, \"event_lag\": %" PRIu64
                        ", \"event_dropped\": %" PRIu64 ", \"telemetry_lag\": %" PRIu64
                        ", \"telemetry_dropped\": %" PRIu64 ", \"delivered\": %" PRIu64
                        ", \"rejected\": %" PRIu64 "}",
                        i ? ", " : "", v.index, v.pid, v.alive ? "true" : "false", v.event_lag,
                        v.event_dropped, v.telemetry_lag, v.telemetry_dropped, v.delivered,
                        v.rejected);
        }
        std::printf("]}\n");
        return;
    }
    std::printf("%s: producer pid %d %s, heartbeat tick %" PRIu64 " %.1f ms ago\n", name.c_str(),
                s.header.producer_pid, to_string(producer_health(s)), p.heartbeat_tick.load(),
                age_ms(p.heartbeat_ns.load()));
    std::printf("events %" PRIu64 ", journal up to %" PRIu64 " (%s), journal dropped %" PRIu64
                ", ring drops %" PRIu64 " events %" PRIu64 " telemetry\n",
                p.next_event_sequence.load(), s.journal_next_sequence.value.load(),
                journal_path_of(s.header).c_str(), s.journal_dropped.value.load(),
                p.events_dropped.load(), p.telemetry_dropped.load());
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

void print_event(const EventRecord& r, bool json) {
    const auto seq = r.header.sequence;
    const char* type = to_string(r.header.type);
    if (json) {
        std::printf("{\"sequence\": %" PRIu64 ", \"time_ns\": %" PRIu64 ", \"type\": \"%s\"", seq,
                    r.header.time_ns, type);
    } else {
        std::printf("%-8" PRIu64 " %-14.6f %-20s", seq, double(r.header.time_ns) / 1e9, type);
    }
    switch (r.header.type) {
        case EventType::kCutBegin:
        case EventType::kCutProgress:
        case EventType::kCutEnd: {
            const CutPayload& c = r.cut;
            std::printf(
                json ? ", \"cut_id\": %u, \"body_id\": %u, \"plane_point_m\": [%g, %g, %g], "
                       "\"plane_normal\": [%g, %g, %g], \"feed_depth_m\": %g}\n"
                     : "cut %u body %u point (%g %g %g) m normal (%g %g %g) feed %g m\n",
                c.cut_id, c.body_id, c.plane_point_m[0], c.plane_point_m[1], c.plane_point_m[2],
                c.plane_normal[0], c.plane_normal[1], c.plane_normal[2], c.feed_depth_m);
            break;
        }
        case EventType::kBodyMoved:
            std::printf(json ? ", \"body_id\": %u, \"position_m\": [%g, %g, %g]}\n"
                             : "body %u position (%g %g %g) m\n",
                        r.body_moved.body_id, r.body_moved.position_m[0],
                        r.body_moved.position_m[1], r.body_moved.position_m[2]);
            break;
        case EventType::kParametersChanged:
            std::printf(json ? ", \"name\": \"%s\", \"value\": %g, \"previous\": %g}\n"
                             : "%s = %g (was %g)\n",
                        r.parameters.name, r.parameters.value, r.parameters.previous_value);
            break;
        case EventType::kDeviceStateChanged:
            std::printf(json ? ", \"state\": \"%s\", \"previous\": \"%s\", \"fault_flags\": %u}\n"
                             : "%s (was %s) faults 0x%x\n",
                        to_string(r.device.state), to_string(r.device.previous),
                        r.device.fault_flags);
            break;
        default:
            std::printf(json ? ", \"scene_id\": %" PRIu64 "}\n" : "scene %" PRIu64 "\n",
                        r.reset.scene_id);
    }
    std::fflush(stdout);
}

void run_tail(const std::string& name, std::optional<std::uint64_t> from, std::uint64_t count,
              bool json) {
    auto c = ConsumerBuilder()
                 .segment_name(name)
                 .from_sequence(from ? *from : ConsumerBuilder::kFromNow)
                 .attach();
    if (!c) fail("tail", "cannot attach to segment", c.error().message);
    std::signal(SIGINT, [](int) { std::_Exit(0); });  // the slot is reclaimed once we are gone
    EventRecord r;
    std::uint64_t printed = 0;
    while (count == 0 || printed < count) {
        if (c->try_next(r) == Poll::kEvent) {
            print_event(r, json);
            ++printed;
            continue;
        }
        const ProducerHealth h = c->producer_health();
        if (h == ProducerHealth::kStopped) return;
        if (h == ProducerHealth::kDead) fail("tail", "segment " + name, "producer died");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
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
    ls->add_flag("--json", o->json, "machine-readable output");
    ls->callback([o] { run_ls(o->json); });

    CLI::App* tail = shm->add_subcommand("tail", "print events live (as a consumer)");
    tail->add_option("name", o->name, "segment name, e.g. kerf.demo")->required();
    tail->add_option("--from", o->from, "replay from this sequence (journal), then follow");
    tail->add_option("--count", o->count, "stop after this many events (0: until stopped)");
    tail->add_flag("--json", o->json, "one JSON object per event");
    tail->callback([o] { run_tail(o->name, o->from, o->count, o->json); });

    CLI::App* stats = shm->add_subcommand("stats", "per-consumer lag, drops and rejections");
    stats->add_option("name", o->name, "segment name, e.g. kerf.demo")->required();
    stats->add_flag("--json", o->json, "machine-readable output");
    stats->callback([o] { run_stats(o->name, o->json); });
}

}  // namespace kerf::cli
