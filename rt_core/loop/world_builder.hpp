// kerf::rt::WorldBuilder — builds the loop's collision world off the real-time thread: first from
// the scene's mesh (kerf-rt loads it at start), then from every generation kerf-display publishes
// through the mesh mailbox. The mailbox reader validates everything (sizes, indices, finiteness,
// materials, generation, content hash); a refused or half-written mesh changes nothing. Each new
// world goes to the loop through a wait-free Handoff, swapped in at a tick boundary; the worlds
// the loop retires are freed here.
//
//   WorldBuilder builder(handoff, producer.layout());
//   builder.build(scene_mesh);   // synchronous, before the loop starts
//   builder.start();             // thread: polls the mailbox every 2 ms, collects retired worlds
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "config/base/result.hpp"
#include "rt_core/ipc/layout.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/loop/handoff.hpp"
#include "rt_core/physics/collision_body.hpp"
#include "rt_core/physics/collision_world.hpp"

namespace kerf::rt {

/// One collision world as the loop installs it: immutable once offered.
struct WorldSnapshot {
    std::uint64_t generation = 0;  ///< mailbox generation (0: the scene's own mesh)
    std::uint32_t body_count = 0;
    std::array<std::shared_ptr<const physics::CollisionBody>, physics::kMaxBodies> bodies{};
    std::array<physics::RigidTransform, physics::kMaxBodies> poses{};
};

/// What the builder has done (read from any thread).
struct WorldBuilderStats {
    std::uint64_t built = 0;          ///< worlds offered to the loop
    std::uint64_t rejected = 0;       ///< mailbox generations refused (reader or build)
    std::uint64_t last_build_ns = 0;  ///< wall time of the last build, ns
};

/// Body `b`'s slice of the mailbox arrays as kerf_physics takes it, what build() hands to
/// CollisionBody::build/update (materials copied into `materials`: the physics enum has the same
/// values as ipc::TriangleMaterial, but a different type). @pre `mesh` validated, b < body_count
physics::CollisionMeshView body_view(const ipc::CollisionMesh& mesh, std::uint32_t b,
                                     std::vector<physics::Material>& materials);

class WorldBuilder {
public:
    /// @pre `handoff` and `segment` outlive the builder
    WorldBuilder(Handoff<WorldSnapshot>& handoff, const ipc::SegmentLayout& segment);
    ~WorldBuilder();  ///< stops the thread
    WorldBuilder(const WorldBuilder&) = delete;
    WorldBuilder& operator=(const WorldBuilder&) = delete;

    /// Builds a world from `mesh` (validated first) and offers it. Non-RT; returns what was wrong.
    Result<std::uint64_t, std::string> build(const ipc::CollisionMesh& mesh);
    /// Starts the mailbox thread (poll period `period_ms`).
    void start(std::uint32_t period_ms = 2);
    /// Stops and joins the thread (idempotent).
    void stop();
    WorldBuilderStats stats() const noexcept;
    /// Replay (input_recording.hpp): a built world is offered only once `*release` reaches its
    /// generation, held until then (a newer one replaces it). nullptr (default): offered at once.
    /// Call before start().
    void gate(const std::atomic<std::uint64_t>* release) noexcept { release_ = release; }
    /// The generation most recently offered to the loop (0: the scene's mesh).
    const std::atomic<std::uint64_t>& offered_generation() const noexcept { return offered_; }
    /// The mailbox reader's last refusal (empty if none). Call from the thread that owns stop().
    std::string last_rejection() const;

private:
    void poll_once();
    void offer_or_hold(std::unique_ptr<WorldSnapshot> world);
    Handoff<WorldSnapshot>& handoff_;
    ipc::MeshMailboxReader reader_;
    std::unique_ptr<ipc::CollisionMesh> scratch_;
    std::shared_ptr<const WorldSnapshot> previous_;  ///< last world built (for chunk reuse)
    std::atomic<std::uint64_t> built_{0}, rejected_{0}, last_build_ns_{0};
    std::atomic<bool> stop_{false};
    const std::atomic<std::uint64_t>* release_ = nullptr;
    std::unique_ptr<WorldSnapshot> held_;  ///< built, waiting for release_ (replay only)
    std::atomic<std::uint64_t> offered_{0};
    std::thread thread_;
    std::string last_rejection_;
};

}  // namespace kerf::rt
