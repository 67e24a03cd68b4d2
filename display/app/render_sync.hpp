// Keeps the renderer's flat copy of the scene (render::RenderMesh, GL-free) in step with a
// CutSession, from the changes the session reports — on the cutting thread, so the frame thread
// only uploads dirty ranges. The geometry is RenderMesh::apply()'s (the one way a session's
// changes reach a RenderMesh); what RenderSync adds is the bodies: it maps session bodies onto the
// renderer's few transform slots: slot 0 is the identity (bodies that never moved share it); a body
// gets a slot of its own when it is severed or first moves, while slots last (then it is drawn
// unmoved and counted).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "display/cut/cut_session.hpp"
#include "display/render/render_mesh.hpp"

namespace kerf::display {

class RenderSync {
public:
    /// Brings `mesh` up to date with `changes` (builds it on the first call or `everything`).
    void apply(const cut::CutSession& session, const cut::SessionChanges& changes);

    /// The flat mesh (empty until the first apply()).
    std::optional<render::RenderMesh>& mesh() noexcept { return mesh_; }
    /// World-from-body matrix of each renderer body slot.
    const std::array<glm::dmat4, render::kMaxBodies>& transforms() const noexcept {
        return transforms_;
    }
    /// Scene bounds at the last build, world frame, m (for the camera).
    glm::dvec3 bounds_min() const noexcept { return lo_; }
    glm::dvec3 bounds_max() const noexcept { return hi_; }
    /// Bodies that needed a slot of their own and found none.
    std::uint64_t bodies_without_slot() const noexcept { return without_slot_; }

private:
    void assign_slots(const cut::CutSession& session, bool rebuilt);
    void set_body_vertices(const cut::CutSession& session, std::uint32_t body, std::uint8_t slot);

    std::optional<render::RenderMesh> mesh_;
    std::array<glm::dmat4, render::kMaxBodies> transforms_{};
    std::vector<std::uint8_t> slot_of_body_;  ///< 0: shares the identity slot
    std::uint8_t next_slot_ = 1;
    std::uint64_t without_slot_ = 0;
    glm::dvec3 lo_{0.0}, hi_{0.0};
    std::vector<mesh::VertexHandle> scratch_vertices_;
};

}  // namespace kerf::display
