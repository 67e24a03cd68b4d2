#include "tests/rt/rt_rig.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "config/load_config.hpp"
#include "display/mesh/scene_arrays.hpp"
#include "firmware_host/transport/socket_report_transport.hpp"
#include "rt_core/loop/collision_mesh_builder.hpp"

namespace kerf::rt::test {

std::string calcaneus_path() {
    return std::string(KERF_SHARED_MESHES) + "/jma_norm01_calcaneus_right.stl";
}

bool have_shared_meshes() { return std::filesystem::exists(calcaneus_path()); }

std::unique_ptr<ipc::CollisionMesh> load_bone(const std::string& path) {
    config::Scene scene;
    scene.name = "test";
    config::SceneBody body;
    body.name = "bone";
    body.mesh.kind = config::MeshSourceKind::kFile;
    body.mesh.path = path;
    body.mesh.units = LengthUnit::kMillimetre;
    scene.bodies.push_back(body);
    auto arrays = mesh::load_scene_arrays(scene, config::PathVars{});
    if (!arrays) return nullptr;
    auto out = std::make_unique<ipc::CollisionMesh>();
    for (const auto& b : *arrays) {
        if (!append_body(*out, b.positions_m, b.indices, b.materials, b.world_from_body)) {
            return nullptr;
        }
    }
    return out;
}

std::unique_ptr<ipc::CollisionMesh> load_scene(const std::string& kerf_toml, std::string& error) {
    auto cfg = config::load_config(kerf_toml);
    if (!cfg) {
        error = cfg.error().message();
        return nullptr;
    }
    auto arrays = mesh::load_scene_arrays(cfg->scene, config::path_vars(*cfg));
    if (!arrays) {
        error = arrays.error();
        return nullptr;
    }
    auto out = std::make_unique<ipc::CollisionMesh>();
    for (const auto& b : *arrays) {
        auto added = append_body(*out, b.positions_m, b.indices, b.materials, b.world_from_body);
        if (!added) {
            error = added.error();
            return nullptr;
        }
    }
    return out;
}

std::string write_script(const std::string& stem, const std::string& text) {
    const std::string path = firmware_host::test::temp_path(stem) + ".csv";
    std::ofstream(path) << text;
    return path;
}

std::string press_script(double depth_m, double hold_s) {
    return "hold,0.05\nmove,0.0," + std::to_string(-depth_m) + ",0.0,0.4\nhold," +
           std::to_string(hold_s) + "\n";
}

Rig::Rig(const RigOptions& options, const std::string& kerf_toml) : options_(options) {
    bone_ = kerf_toml.empty() ? load_bone(calcaneus_path()) : load_scene(kerf_toml, error_);
    if (!bone_) {
        if (error_.empty()) error_ = "could not load " + calcaneus_path();
        return;
    }
    const std::string segment = "kerf.rt-test-" + std::to_string(getpid()) + "-" +
                                std::to_string(reinterpret_cast<std::uintptr_t>(this));
    if (options.replay) {
        auto producer = ipc::ProducerBuilder().segment_name(segment).create();
        if (!producer) {
            error_ = producer.error().message();
            return;
        }
        producer_.emplace(std::move(*producer));
        replay_device_ = std::make_unique<ReplayDevice>(*options.replay, ReplayWorldGate{});
        if (make_loop(*replay_device_)) loop_->replay_from(replay_device_.get());
        return;
    }
    std::vector<std::string> args = {"--protocol", "kerf"};
    if (!options.script.empty()) {
        args.push_back("--script");
        args.push_back(write_script("rt_hand", options.script));
    }
    args.insert(args.end(), options.hapsim_args.begin(), options.hapsim_args.end());
    sim_ = std::make_unique<firmware_host::test::HapsimProcess>(args);
    if (!sim_->ready()) {
        error_ = "kerf-hapsim did not start: " + sim_->output();
        return;
    }
    auto producer = ipc::ProducerBuilder().segment_name(segment).create();
    if (!producer) {
        error_ = producer.error().message();
        return;
    }
    producer_.emplace(std::move(*producer));
    if (!open_device()) return;
}

Rig::~Rig() {
    if (reconnector_) reconnector_->stop();
    if (builder_) builder_->stop();
    if (loop_ && !loop_->waiting_for_device()) {
        if (auto* hid = dynamic_cast<firmware_host::KerfHidDevice*>(&loop_->device()))
            hid->shutdown(200);
    }
    reconnector_.reset();
    builder_.reset();
    loop_.reset();
}

namespace {

/// The emulator's Kerf HID device over its socket, as kerf-rt opens it (watchdog 100 ms:
/// lockstep, the emulator's clock only moves with our packets).
Result<std::unique_ptr<firmware_host::KerfHidDevice>, std::string> open_hid(
    const std::string& socket_path) {
    auto socket = firmware_host::SeqpacketSocket::connect(socket_path);
    if (!socket) return Err{socket.error().message()};
    firmware_host::KerfHidOptions o;
    o.watchdog_ms = 100;
    o.feature_timeout_ms = 300;
    auto dev = firmware_host::KerfHidDevice::open(
        std::make_unique<firmware_host::SocketReportTransport>(std::move(*socket)), o);
    if (!dev) return Err{dev.error().message()};
    return std::move(*dev);
}

}  // namespace

bool Rig::open_device() {
    auto dev = open_hid(sim_->socket_path());
    if (!dev) {
        error_ = dev.error();
        return false;
    }
    device_ = std::move(*dev);
    if (!make_loop(*device_)) return false;
    reconnector_ = std::make_unique<DeviceReconnector>(
        loop_->device_link(), loop_->device_handoff(),
        [path =
             sim_->socket_path()]() -> Result<std::unique_ptr<firmware_host::Device>, std::string> {
            auto d = open_hid(path);
            if (!d) return Err{d.error()};
            return std::unique_ptr<firmware_host::Device>(std::move(*d));
        });
    reconnector_->start();
    return true;
}

bool Rig::make_loop(firmware_host::Device& device) {
    LoopSettings settings;
    settings.read_timeout_us = options_.read_timeout_us;
    settings.lockstep = options_.lockstep;
    settings.motion_scale = options_.motion_scale;
    settings.device_origin_in_world_m = device_origin_above(*bone_, 0.01);
    firmware_host::SafetyLimits limits;
    limits.peak_force_n = 8.0;
    limits.continuous_force_n = 4.0;
    limits.ramp_in_s = 0.02;
    limits.engage_quiet_ticks = 10;
    loop_ = std::make_unique<HapticLoop>(device, *producer_, log_, settings,
                                         physics::PhysicsParams{}, limits);
    builder_ = std::make_unique<WorldBuilder>(loop_->world_handoff(), producer_->layout());
    auto built = builder_->build(*bone_);
    if (!built) {
        error_ = built.error();
        return false;
    }
    if (options_.start_builder) builder_->start();
    loop_->prime();
    return true;
}

void Rig::tick() {
    // As the runner: without a device (lost, being re-opened) the clock paces lockstep ticks. A
    // replay waits for nothing (its recording says when the device came back).
    if (loop_->waiting_for_device() && !options_.replay)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    TickTiming t;
    t.start_ns = monotonic_ns();
    loop_->tick(t);
    loop_->record_compute(monotonic_ns() - t.start_ns);
}

bool Rig::tick_until_force(int max_ticks) {
    for (int i = 0; i < max_ticks; ++i) {
        tick();
        if (force_norm() > 0.05) return true;
    }
    return false;
}

double Rig::force_norm() const {
    const auto& f = loop_->last_force_n();
    return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
}

}  // namespace kerf::rt::test
