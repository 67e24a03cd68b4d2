// An in-process kerf-rt for tests: the real kerf-hapsim process (lockstep, a scripted hand), the
// real Kerf HID device code over its socket, a real session segment and journal, a real bone from
// ../shared/meshes as the collision world (built by the WorldBuilder, as kerf-rt does), and the
// HapticLoop ticked by the test (tick()) or by run_loop().
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "firmware_host/device/kerf_hid_device.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/loop/device_reconnector.hpp"
#include "rt_core/loop/haptic_loop.hpp"
#include "rt_core/loop/input_recording.hpp"
#include "rt_core/loop/loop_runner.hpp"
#include "rt_core/loop/rt_log.hpp"
#include "rt_core/loop/world_builder.hpp"
#include "tests/firmware_host/hapsim_process.hpp"

namespace kerf::rt::test {

/// The calcaneus (CT, 58k triangles, mm) from the shared meshes.
std::string calcaneus_path();
/// Whether the shared meshes are there (tests skip visibly when not).
bool have_shared_meshes();

/// Loads a mesh file (units mm) through the scene loader into a collision mesh of one body.
std::unique_ptr<ipc::CollisionMesh> load_bone(const std::string& path);
/// The scene of a kerf.toml as kerf-rt loads it (nullptr and `error` on failure).
std::unique_ptr<ipc::CollisionMesh> load_scene(const std::string& kerf_toml, std::string& error);

/// Writes a hapsim hand script to a temp file and returns its path.
std::string write_script(const std::string& stem, const std::string& text);

/// A hand script: hold, then press the tool `depth_m` below the start (along -y) and hold there.
std::string press_script(double depth_m, double hold_s = 60.0);

struct RigOptions {
    std::string script;                    ///< hand script text
    std::vector<std::string> hapsim_args;  ///< more kerf-hapsim arguments
    std::uint32_t read_timeout_us = 100'000;
    bool start_builder = true;  ///< poll the mailbox on a thread
    bool lockstep = true;       ///< false: kerf-hapsim runs --realtime, the loop is paced
    double motion_scale = 1.0;  ///< LoopSettings::motion_scale (NaN: a broken configuration)
    /// Replay this recording (ReplayDevice, HapticLoop::replay_from) instead of running
    /// kerf-hapsim: no emulator, no reconnector; the same loop settings, world and limits.
    const Recording* replay = nullptr;
};

class Rig {
public:
    /// `kerf_toml` empty: the raw calcaneus file is the world. Else the scene of that kerf.toml,
    /// loaded as kerf-rt loads it (same loader, same transforms), so a display-side CutSession
    /// built from the same configuration shares its frame.
    explicit Rig(const RigOptions& options, const std::string& kerf_toml = {});
    ~Rig();

    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    /// One tick as the runner does it (lockstep timing).
    void tick();
    /// Ticks until the loop commands a non-zero force (or `max_ticks`); true when it did.
    bool tick_until_force(int max_ticks);
    double force_norm() const;

    firmware_host::test::HapsimProcess& sim() { return *sim_; }  ///< not in a replay
    HapticLoop& loop() { return *loop_; }
    ipc::Producer& producer() { return *producer_; }
    WorldBuilder& builder() { return *builder_; }
    /// The thread that re-opens the device after a loss (as kerf-rt runs it).
    DeviceReconnector& reconnector() { return *reconnector_; }

private:
    bool open_device();
    bool make_loop(firmware_host::Device& device);
    RigOptions options_;
    std::string error_;
    std::unique_ptr<firmware_host::test::HapsimProcess> sim_;
    std::unique_ptr<firmware_host::KerfHidDevice> device_;
    std::unique_ptr<ReplayDevice> replay_device_;
    std::optional<ipc::Producer> producer_;
    RtLog log_;
    std::unique_ptr<ipc::CollisionMesh> bone_;
    std::unique_ptr<HapticLoop> loop_;
    std::unique_ptr<WorldBuilder> builder_;
    std::unique_ptr<DeviceReconnector> reconnector_;
};

}  // namespace kerf::rt::test
