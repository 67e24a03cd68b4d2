#include "rt_core/app/rt_process.hpp"

#include <signal.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "config/data_dir.hpp"
#include "config/device_profile.hpp"
#include "config/load_config.hpp"
#include "display/mesh/scene_arrays.hpp"
#include "firmware_host/open/open_device.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/loop/collision_mesh_builder.hpp"
#include "rt_core/loop/haptic_loop.hpp"
#include "rt_core/loop/input_recording.hpp"
#include "rt_core/loop/lockstep_world_sync.hpp"
#include "rt_core/loop/loop_runner.hpp"
#include "rt_core/loop/profile_reloader.hpp"
#include "rt_core/loop/realtime_setup.hpp"
#include "rt_core/loop/rt_log.hpp"
#include "rt_core/loop/scene_mapping.hpp"
#include "rt_core/loop/world_builder.hpp"
#include "rt_core/physics/physics_params_from_profile.hpp"

namespace kerf::rt {
namespace {

int fail(const std::string& what) {
    std::fprintf(stderr, "kerf-rt: %s\n", what.c_str());
    return 1;
}

/// The device profile the command line asks for (or kerf.toml's).
Result<config::DeviceProfile, std::string> pick_device(const config::Config& cfg,
                                                       const RtOptions& o, bool replay) {
    config::DeviceProfile profile = cfg.device;
    if (!o.device.empty()) {
        const std::string stem(config::device_profile_stem(o.device));
        auto loaded = config::load_device_profile(cfg.config_dir / "devices" / (stem + ".toml"));
        if (!loaded) return Err{loaded.error().message()};
        profile = std::move(*loaded);
        if (o.device.rfind("hid:", 0) == 0) profile.ids.serial = o.device.substr(4);
    }
    if (o.lockstep && !replay) {
        if (profile.kind != config::DeviceKind::kSimulated) {
            return Err{std::string("--lockstep needs the simulated device (kerf-hapsim)")};
        }
        profile.emulator.lockstep = true;
    }
    return profile;
}

/// The scene's bodies as one collision mesh (the same loader / generator as the display).
Result<std::unique_ptr<ipc::CollisionMesh>, std::string> scene_mesh(const config::Config& cfg) {
    auto bodies = mesh::load_scene_arrays(cfg.scene, config::path_vars(cfg));
    if (!bodies) return Err{bodies.error()};
    auto out = std::make_unique<ipc::CollisionMesh>();
    for (const mesh::BodyArrays& b : *bodies) {
        auto added = append_body(*out, b.positions_m, b.indices, b.materials, b.world_from_body);
        if (!added)
            return Err{"scene " + cfg.scene.name + " body '" + b.name + "': " + added.error()};
    }
    return out;
}

std::string summary(const LoopStats& s, std::uint64_t worlds_rejected, std::uint64_t reloads,
                    std::uint64_t refused, const ReconnectStats& reconnect) {
    const auto us = [](std::uint64_t ns) { return double(ns) / 1000.0; };
    char buf[1280];
    std::snprintf(
        buf, sizeof buf,
        "kerf-rt summary: ticks %llu, overruns %llu, late wakes %llu (deadlines skipped %llu), "
        "safe-state entries %llu (%llu ticks)\n"
        "  wake latency us: p50 %.1f  p99 %.1f  p99.9 %.1f  max %.1f\n"
        "  tick work us:    p50 %.1f  p99 %.1f  p99.9 %.1f  max %.1f\n"
        "  events %llu (not journalled %llu), device reads not ok %llu (no new sample %llu, "
        "malformed %llu, error %llu; stale episodes %llu), worlds swapped %llu "
        "(mailbox refused %llu), profile reloads %llu (refused %llu)\n"
        "  device lost %llu, re-opened %llu (attempts %llu), ticks without a device %llu\n",
        (unsigned long long)s.ticks, (unsigned long long)s.overruns,
        (unsigned long long)s.late_wakes, (unsigned long long)s.missed_deadlines,
        (unsigned long long)s.safe_state_entries, (unsigned long long)s.safe_state_ticks,
        us(s.wake_latency.percentile(0.5)), us(s.wake_latency.percentile(0.99)),
        us(s.wake_latency.percentile(0.999)), us(s.wake_latency.max_ns()),
        us(s.compute.percentile(0.5)), us(s.compute.percentile(0.99)),
        us(s.compute.percentile(0.999)), us(s.compute.max_ns()),
        (unsigned long long)s.events_published, (unsigned long long)s.events_not_journalled,
        (unsigned long long)s.device_not_ok, (unsigned long long)s.device_no_data,
        (unsigned long long)s.device_malformed, (unsigned long long)s.device_error,
        (unsigned long long)s.stale_episodes, (unsigned long long)s.worlds_swapped,
        (unsigned long long)worlds_rejected, (unsigned long long)reloads,
        (unsigned long long)refused, (unsigned long long)s.devices_lost,
        (unsigned long long)s.devices_reopened, (unsigned long long)reconnect.attempts,
        (unsigned long long)s.device_lost_ticks);
    return buf;
}

bool write_trace(const std::string& path, const std::vector<TraceRow>& rows, std::uint64_t n) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp);
        f << "tick,x_m,y_m,z_m,fx_n,fy_n,fz_n\n";
        char line[256];
        for (std::uint64_t i = 0; i < n; ++i) {
            const TraceRow& r = rows[i];
            std::snprintf(line, sizeof line, "%llu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                          (unsigned long long)i, r.tool_position_m[0], r.tool_position_m[1],
                          r.tool_position_m[2], r.force_n[0], r.force_n[1], r.force_n[2]);
            f << line;
        }
        if (!f.flush()) return false;
    }
    return std::rename(tmp.c_str(), path.c_str()) == 0;
}

/// The non-empty bins of the loop's histograms: upper edge (us; the overflow bin: the largest
/// value seen), wake-latency count, tick-work count.
bool write_histograms(const std::string& path, const LoopStats& s) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp);
        f << "upper_us,wake_latency,tick_work\n";
        for (std::uint32_t b = 0; b < LatencyHistogram::kBins; ++b) {
            if (!s.wake_latency.bin(b) && !s.compute.bin(b)) continue;
            const std::uint64_t edge = b + 1 < LatencyHistogram::kBins
                                           ? LatencyHistogram::upper_edge(b)
                                           : std::max(s.wake_latency.max_ns(), s.compute.max_ns());
            f << double(edge) / 1000.0 << "," << s.wake_latency.bin(b) << "," << s.compute.bin(b)
              << "\n";
        }
        if (!f.flush()) return false;
    }
    return std::rename(tmp.c_str(), path.c_str()) == 0;
}

}  // namespace

int run_rt_process(const RtOptions& o) {
    // Signals are taken by this thread with sigtimedwait; every thread started below inherits
    // the mask, so none of them (the real-time one included) is ever interrupted by one.
    sigset_t signals;
    sigemptyset(&signals);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&signals, s);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    auto cfg = config::load_config(o.config.empty() ? config::data_file("kerf.toml") : o.config);
    if (!cfg) return fail(cfg.error().message());
    const bool replay = !o.replay_path.empty();
    auto device_profile = pick_device(*cfg, o, replay);
    if (!device_profile) return fail(device_profile.error());
    const config::RealtimeSettings& rts = cfg->main.realtime;
    const double period_s = double(rts.period_ns) * 1e-9;

    const RealtimeItem heap = keep_freed_memory();  // before the meshes: their pages are reused
    auto mesh = scene_mesh(*cfg);
    if (!mesh) return fail(mesh.error());

    // The device: the real one (or the emulator), or replayed input; the loop records itself.
    firmware_host::OpenOverrides overrides{o.firmware_path, o.socket_path, {}};
    Recording recording;
    std::atomic<std::uint64_t> world_release{0};
    std::unique_ptr<firmware_host::Device> device;
    std::unique_ptr<ReplayDevice> replay_device;
    if (replay) {
        auto loaded = load_recording(o.replay_path);
        if (!loaded) return fail(loaded.error());
        recording = std::move(*loaded);
        if (recording.period_ns != std::uint64_t(rts.period_ns))
            return fail("--replay: recorded at a period of " + std::to_string(recording.period_ns) +
                        " ns, [realtime] period_ns is " + std::to_string(rts.period_ns));
    } else {
        auto opened = firmware_host::open_device(*device_profile, overrides);
        if (!opened) return fail(opened.error().message());
        device = std::move(*opened);
    }
    std::unique_ptr<InputRecorder> recorder;
    if (!o.record_path.empty()) {
        // Lockstep is paced by the emulator, not the clock: a full ring waits for the drain
        // (a loaded machine starved it: "ticks dropped" and no recording) instead of dropping.
        auto started = InputRecorder::start(o.record_path, std::uint64_t(rts.period_ns),
                                            o.lockstep ? WhenFull::kWait : WhenFull::kDrop);
        if (!started) return fail(started.error());
        recorder = std::move(*started);
    }

    std::error_code ec;
    std::filesystem::create_directories(cfg->journal_dir, ec);
    if (ec) return fail("journal folder " + cfg->journal_dir.string() + ": " + ec.message());
    const std::string session =
        o.session_name.empty() ? cfg->main.shm.session_name : o.session_name;
    ipc::ProducerBuilder producer_builder;
    producer_builder.segment_name(session).journal_dir(cfg->journal_dir.string());
    if (!cfg->main.shm.group.empty()) producer_builder.group(cfg->main.shm.group);
    auto producer = producer_builder.create();
    if (!producer) return fail(producer.error().message());

    LoopSettings settings;
    settings.period_ns = rts.period_ns;
    settings.misses_to_safe_state = rts.consecutive_misses_to_safe_state;
    // Lockstep: wait for the emulator's answer to each packet, up to 5 s. With 200 ms, under load
    // (load 12-16 on 2 cores) an answer came later, the read returned no sample and every later
    // read took the previous step's report (10,091 "no new sample" in one demo; a duplicated
    // sample at tick 1607 in the determinism test): a different run. An emulator that died closes
    // its socket (the read says disconnected at once); one that hangs costs 5 s a tick.
    settings.read_timeout_us = o.lockstep ? 5'000'000 : 0;
    settings.lockstep = o.lockstep || replay;
    apply_scene_mapping(cfg->scene, **mesh, settings);  // [device_mapping], [planned_cut]
    const physics::PhysicsParams physics = physics::physics_params_from_profile(cfg->force);
    const auto safety = firmware_host::safety_limits_from(*device_profile, &cfg->force, period_s);

    RtLog log;
    RtLogDrain drain(log);
    // Set by SIGINT/SIGTERM: the loop stops after its tick, and lockstep/replay waits end at once.
    std::atomic<bool> stop{false}, finished{false};
    if (replay) replay_device = std::make_unique<ReplayDevice>(recording, ReplayWorldGate{});
    firmware_host::Device* loop_device = replay ? replay_device.get() : device.get();
    std::unique_ptr<LockstepWorldSync> world_sync;  // lockstep: cut meshes at fixed ticks
    if (o.lockstep && !replay) {
        // 10 s a wait: a cut the display refused publishes no world, and the run must go on.
        world_sync = std::make_unique<LockstepWorldSync>(*loop_device);
        world_sync->await_first_world(o.await_display);
        world_sync->stop_waiting_when(stop);
        loop_device = world_sync.get();
    }
    auto loop =
        std::make_unique<HapticLoop>(*loop_device, *producer, log, settings, physics, safety);
    if (world_sync) loop->keep_in_front(*world_sync);  // a re-opened device goes behind it
    // Every tick, lost device and re-opened ones included, recorded from inside the loop.
    if (recorder) loop->record_to(recorder.get());
    if (replay_device) loop->replay_from(replay_device.get());  // recorded stalls and re-opens
    // A lost device is opened again by this thread (normal priority), as at start.
    DeviceReconnector reconnector(
        loop->device_link(), loop->device_handoff(),
        [profile = *device_profile, overrides,
         replay]() -> Result<std::unique_ptr<firmware_host::Device>, std::string> {
            if (replay) return Err{std::string("a replay has no device to re-open")};
            auto opened = firmware_host::open_device(profile, overrides);
            if (!opened) return Err{opened.error().message()};
            return std::move(*opened);
        });
    WorldBuilder builder(loop->world_handoff(), producer->layout());
    if (replay) {  // worlds swap at the recorded ticks (input_recording.hpp)
        builder.gate(&world_release);
        ReplayWorldGate gate{&world_release, &builder.offered_generation()};
        gate.keep_alive = [](void* l) noexcept { static_cast<HapticLoop*>(l)->keep_alive(); };
        gate.keep_alive_context = loop.get();
        gate.stop = &stop;
        replay_device->set_gate(gate);
    }
    if (world_sync) {
        builder.gate(&world_release);
        world_sync->attach(*loop, world_release, builder.offered_generation());
    }
    if (auto built = builder.build(**mesh); !built) return fail("scene mesh: " + built.error());
    std::printf("kerf-rt: session %s, device %s, scene %s (%u bodies, %u triangles), %s\n",
                session.c_str(), device_profile->name.c_str(), cfg->scene.name.c_str(),
                (*mesh)->body_count, (*mesh)->index_count / 3,
                o.lockstep ? "lockstep (paced by the emulator)" : "real time");
    std::printf("kerf-rt: %s\n", describe_mapping(cfg->scene, settings).c_str());
    std::printf("kerf-rt: %s: %s\n", heap.what.c_str(), heap.result.c_str());
    mesh->reset();
    builder.start();
    if (!replay) reconnector.start();  // a replay re-enacts the recorded re-opens itself
    const auto profile_path = cfg->config_dir / "force" / (cfg->main.profiles.force + ".toml");
    ProfileReloader reloader(loop->profile_handoff(), profile_path, cfg->force, *device_profile,
                             period_s, physics);
    if (!reloader.start())
        spdlog::warn("kerf-rt: no file watch ({}); SIGHUP still reloads", reloader.last_error());

    std::vector<TraceRow> trace;
    std::uint64_t trace_rows = 0;
    const auto max_ticks = replay ? std::uint64_t(recording.inputs.size())
                                  : std::uint64_t(std::llround(o.duration_s / period_s));
    if (!o.trace_path.empty()) trace.resize(max_ticks ? max_ticks : 600'000);

    std::atomic<int> status{0};
    std::thread rt_thread([&] {
        const RealtimeReport report = apply_realtime(rts);
        std::printf("kerf-rt: real-time report\n%s", report.format().c_str());
        std::fflush(stdout);
        if (report.degraded() && rts.require_realtime) {
            std::fprintf(stderr, "kerf-rt: require_realtime = true and a request was denied\n");
            status = 3;
        } else {
            loop->set_degraded_realtime(report.degraded());
            RunOptions run{rts.period_ns, o.lockstep || replay, max_ticks, &stop,
                           trace,         &trace_rows};
            run_loop(*loop, run);
        }
        finished.store(true, std::memory_order_release);
    });

    const timespec poll_period{0, 20'000'000};
    while (!finished.load(std::memory_order_acquire)) {
        const int sig = sigtimedwait(&signals, nullptr, &poll_period);
        if (sig == SIGHUP) reloader.request_reload();
        if (sig == SIGINT || sig == SIGTERM) stop.store(true, std::memory_order_release);
    }
    rt_thread.join();
    reconnector.stop();
    reloader.stop();
    builder.stop();
    // The loop's device, or the one behind a lockstep sync (the first or a re-opened one).
    auto* hid = dynamic_cast<firmware_host::KerfHidDevice*>(world_sync ? &world_sync->inner()
                                                                       : &loop->device());
    if (hid) {
        if (!loop->waiting_for_device()) hid->shutdown(200);
    }
    producer->stop();
    const WorldBuilderStats ws = builder.stats();
    std::printf("%s", summary(loop->stats(), ws.rejected, reloader.accepted(), reloader.refused(),
                              reconnector.stats())
                          .c_str());
    if (const auto fault = loop->checks().first()) {
        std::printf("  FAULT: check `%s` failed at %s:%u (%u times); force was held at zero\n",
                    fault->condition, fault->file, fault->line, loop->checks().failures());
    }
    if (!o.trace_path.empty() && !write_trace(o.trace_path, trace, trace_rows)) {
        return fail("could not write the trace " + o.trace_path);
    }
    if (!o.histogram_path.empty() && !write_histograms(o.histogram_path, loop->stats()))
        return fail("could not write the histograms " + o.histogram_path);
    if (world_sync) {
        std::printf(
            "kerf-rt: lockstep: %llu collision worlds (%scut meshes) swapped in two ticks "
            "after they were due, %llu not published within %d s\n",
            (unsigned long long)world_sync->synced(),
            o.await_display ? "the display's first, then " : "",
            (unsigned long long)world_sync->timed_out(), 10);
    }
    if (replay) {
        std::printf(
            "kerf-rt: replayed %llu of %zu recorded ticks from %s; worlds not ready in "
            "time %llu\n",
            (unsigned long long)replay_device->ticks(), recording.inputs.size(),
            o.replay_path.c_str(), (unsigned long long)replay_device->late_worlds());
    }
    if (recorder) {
        auto recorded = recorder->stop();
        if (!recorded) return fail(recorded.error());
        std::printf("kerf-rt: recorded %llu ticks of device input into %s\n",
                    (unsigned long long)*recorded, o.record_path.c_str());
    }
    return status.load();
}

}  // namespace kerf::rt
