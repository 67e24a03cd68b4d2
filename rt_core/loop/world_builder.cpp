#include "rt_core/loop/world_builder.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <vector>

namespace kerf::rt {
namespace {

std::uint64_t now_ns() {
    return std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                             std::chrono::steady_clock::now().time_since_epoch())
                             .count());
}

}  // namespace

physics::CollisionMeshView body_view(const ipc::CollisionMesh& mesh, std::uint32_t b,
                                     std::vector<physics::Material>& materials) {
    const ipc::MeshBodyEntry& e = mesh.bodies[b];
    materials.resize(e.index_count / 3);
    for (std::uint32_t t = 0; t < e.index_count / 3; ++t)
        materials[t] = physics::Material(mesh.materials[e.index_offset / 3 + t]);
    physics::CollisionMeshView view;
    view.positions_m = {mesh.vertices_m.data() + 3u * e.vertex_offset, 3u * e.vertex_count};
    view.indices = {mesh.indices.data() + e.index_offset, e.index_count};
    view.materials = materials;
    view.world_from_body = physics::RigidTransform::from_column_major(e.world_from_body);
    return view;
}

WorldBuilder::WorldBuilder(Handoff<WorldSnapshot>& handoff, const ipc::SegmentLayout& segment)
    : handoff_(handoff), reader_(segment), scratch_(std::make_unique<ipc::CollisionMesh>()) {}

WorldBuilder::~WorldBuilder() { stop(); }

Result<std::uint64_t, std::string> WorldBuilder::build(const ipc::CollisionMesh& mesh) {
    std::string where;
    const ipc::MeshFault fault = ipc::validate_mesh(mesh, where);
    if (fault != ipc::MeshFault::kNone) {
        return Err{"collision mesh: " + std::string(ipc::to_string(fault)) + ": " + where};
    }
    const std::uint64_t t0 = now_ns();
    auto world = std::make_unique<WorldSnapshot>();
    world->generation = mesh.generation;
    world->body_count = mesh.body_count;
    std::vector<physics::Material> materials;
    for (std::uint32_t b = 0; b < mesh.body_count; ++b) {
        const physics::CollisionMeshView view = body_view(mesh, b, materials);
        const physics::CollisionBody* before =
            previous_ && b < previous_->body_count ? previous_->bodies[b].get() : nullptr;
        auto body = before ? physics::CollisionBody::update(*before, view)
                           : physics::CollisionBody::build(view);
        if (!body) {
            return Err{"collision mesh body " + std::to_string(b) + ": " +
                       std::string(physics::to_string(body.error().error)) + " at element " +
                       std::to_string(body.error().index)};
        }
        // The first build of a body also runs one throwaway update: its fresh copies fault in
        // the pages the first update after a cut will reuse (see keep_freed_memory()).
        if (!before) (void)physics::CollisionBody::update(**body, view);
        world->bodies[b] = std::shared_ptr<const physics::CollisionBody>(std::move(*body));
        world->poses[b] = view.world_from_body;
    }
    auto copy = std::make_shared<WorldSnapshot>(*world);  // shares the bodies, for reuse
    previous_ = std::move(copy);
    offer_or_hold(std::move(world));
    last_build_ns_.store(now_ns() - t0, std::memory_order_relaxed);
    built_.fetch_add(1, std::memory_order_relaxed);
    return mesh.generation;
}

void WorldBuilder::start(std::uint32_t period_ms) {
    stop_.store(false, std::memory_order_release);
    thread_ = std::thread([this, period_ms] {
        while (!stop_.load(std::memory_order_acquire)) {
            poll_once();
            std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
        }
        handoff_.collect();
    });
}

void WorldBuilder::stop() {
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

void WorldBuilder::offer_or_hold(std::unique_ptr<WorldSnapshot> world) {
    if (release_ && world->generation > release_->load(std::memory_order_acquire)) {
        held_ = std::move(world);
        return;
    }
    const std::uint64_t generation = world->generation;
    handoff_.offer(std::move(world));
    offered_.store(generation, std::memory_order_release);
}

void WorldBuilder::poll_once() {
    handoff_.collect();
    if (held_) offer_or_hold(std::move(held_));
    const ipc::MailboxRead read = reader_.try_take_newest(*scratch_);
    if (read == ipc::MailboxRead::kRejected) {
        rejected_.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    if (read != ipc::MailboxRead::kNew) return;
    auto built = build(*scratch_);
    if (!built) {
        rejected_.fetch_add(1, std::memory_order_relaxed);
        last_rejection_ = built.error();
        spdlog::warn("kerf-rt: mailbox generation {} not built: {}", scratch_->generation,
                     built.error());
    }
}

WorldBuilderStats WorldBuilder::stats() const noexcept {
    return {built_.load(std::memory_order_relaxed), rejected_.load(std::memory_order_relaxed),
            last_build_ns_.load(std::memory_order_relaxed)};
}

std::string WorldBuilder::last_rejection() const {
    return last_rejection_.empty() ? reader_.last_rejection() : last_rejection_;
}

}  // namespace kerf::rt
