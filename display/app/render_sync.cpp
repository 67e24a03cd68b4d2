#include "display/app/render_sync.hpp"

#include <glm/gtc/type_ptr.hpp>

namespace kerf::display {
namespace {

bool is_identity(const cut::RigidPose& p) {
    return p.position_m == cut::Vec3(0, 0, 0) && p.orientation_wxyz[0] == 1.0 &&
           p.orientation_wxyz[1] == 0.0 && p.orientation_wxyz[2] == 0.0 &&
           p.orientation_wxyz[3] == 0.0;
}

}  // namespace

void RenderSync::set_body_vertices(const cut::CutSession& session, std::uint32_t body,
                                   std::uint8_t slot) {
    scratch_vertices_.clear();
    for (const auto v : session.mesh().vertices())
        if (session.body_of(v) == body) scratch_vertices_.push_back(v);
    mesh_->set_body(session.mesh(), scratch_vertices_, slot);
}

void RenderSync::assign_slots(const cut::CutSession& session, bool rebuilt) {
    const auto bodies = session.bodies();
    slot_of_body_.resize(bodies.size(), 0);
    for (std::uint32_t b = 0; b < bodies.size(); ++b) {
        std::uint8_t& slot = slot_of_body_[b];
        const bool needs_own = bodies[b].parent != cut::kNoBody || !is_identity(bodies[b].pose);
        if (slot == 0 && needs_own) {
            if (next_slot_ < render::kMaxBodies) {
                slot = next_slot_++;
                set_body_vertices(session, b, slot);
            } else {
                ++without_slot_;
                continue;
            }
        } else if (slot != 0 && rebuilt) {
            set_body_vertices(session, b, slot);
        }
        if (slot != 0) transforms_[slot] = glm::make_mat4(bodies[b].pose.matrix().data());
    }
}

void RenderSync::apply(const cut::CutSession& session, const cut::SessionChanges& changes) {
    const mesh::TriMesh& m = session.mesh();
    bool rebuilt = false;
    if (changes.everything || !mesh_) {
        mesh_ = render::RenderMesh::build(m);
        slot_of_body_.clear();
        next_slot_ = 1;
        transforms_.fill(glm::dmat4(1.0));
        rebuilt = true;
        lo_ = glm::dvec3(1e300);
        hi_ = glm::dvec3(-1e300);
        for (const auto v : m.vertices()) {
            const auto p = m.point(v);
            lo_ = glm::min(lo_, glm::dvec3(p[0], p[1], p[2]));
            hi_ = glm::max(hi_, glm::dvec3(p[0], p[1], p[2]));
        }
    } else {
        rebuilt = mesh_->apply(m, changes).rebuilt;
        // Changed vertices of bodies drawn with their own transform keep their slot.
        for (const cut::IndexRange& r : changes.vertices) {
            for (std::uint32_t i = r.first; i < r.first + r.count && i < m.n_vertices(); ++i) {
                const mesh::VertexHandle v(static_cast<int>(i));
                const std::uint32_t b = session.body_of(v);
                if (b < slot_of_body_.size() && slot_of_body_[b] != 0) {
                    const mesh::VertexHandle one[1] = {v};
                    mesh_->set_body(m, one, slot_of_body_[b]);
                }
            }
        }
    }
    if (changes.everything || changes.bodies || changes.poses || rebuilt)
        assign_slots(session, rebuilt);
}

}  // namespace kerf::display
