#include "display/render/render_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "display/cut/cross_section.hpp"

namespace kerf::render {

namespace {

using mesh::FaceHandle;
using mesh::TriMesh;
using mesh::VertexHandle;

constexpr std::uint32_t kNoSlot = std::numeric_limits<std::uint32_t>::max();

SurfaceKind kind_of(mesh::Material m) noexcept {
    return m == mesh::Material::kCancellous ? SurfaceKind::kCanal : SurfaceKind::kCortical;
}

SurfaceKind cut_kind_of(mesh::Material m) noexcept {
    return m == mesh::Material::kCancellous ? SurfaceKind::kCutCanal : SurfaceKind::kCutCortical;
}

// True when `f` carries the cut library's cap-face mark.
bool is_cap(const TriMesh& m, FaceHandle f) {
    OpenMesh::FPropHandleT<std::uint8_t> h;
    if (!m.get_property_handle(h, cut::kCapFaceProperty)) return false;
    return m.property(h, f) != cut::kCapNone;
}

// An orthonormal (u, v) frame of the plane with normal `n`, continuous in n away from |n.x| = 0.9.
void plane_frame(const OpenMesh::Vec3d& n, OpenMesh::Vec3d& u, OpenMesh::Vec3d& v) {
    const OpenMesh::Vec3d a =
        std::abs(n[0]) < 0.9 ? OpenMesh::Vec3d(1, 0, 0) : OpenMesh::Vec3d(0, 1, 0);
    u = OpenMesh::cross(a, n).normalized();
    v = OpenMesh::cross(n, u);
}

RenderVertex make_vertex(const OpenMesh::Vec3d& p, const OpenMesh::Vec3d& n, SurfaceKind kind,
                         std::uint8_t body) {
    RenderVertex r{};
    for (int i = 0; i < 3; ++i) {
        r.position[i] = static_cast<float>(p[i]);
        r.normal[i] = static_cast<float>(n[i]);
    }
    r.kind = static_cast<std::uint8_t>(kind);
    r.body = body;
    return r;
}

bool same(const RenderVertex& a, const RenderVertex& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace

// ---- DirtyRanges --------------------------------------------------------------------------

void DirtyRanges::mark(std::uint32_t i) { mark_range(i, 1); }

void DirtyRanges::mark_range(std::uint32_t first, std::uint32_t count) {
    if (count == 0) return;
    if (!marks_.empty()) {
        Range& last = marks_.back();
        if (first >= last.first && first <= last.first + last.count) {
            last.count = std::max(last.count, first + count - last.first);
            return;
        }
    }
    marks_.push_back({first, count});
}

std::span<const DirtyRanges::Range> DirtyRanges::ranges() {
    if (marks_.empty()) return merged_;
    marks_.insert(marks_.end(), merged_.begin(), merged_.end());
    std::sort(marks_.begin(), marks_.end(),
              [](const Range& a, const Range& b) { return a.first < b.first; });
    merged_.clear();
    for (const Range& r : marks_) {
        if (!merged_.empty()) {
            Range& last = merged_.back();
            const std::uint64_t end = std::uint64_t{last.first} + last.count;
            if (r.first <= end + kMergeGap) {
                last.count = static_cast<std::uint32_t>(
                    std::max<std::uint64_t>(end, std::uint64_t{r.first} + r.count) - last.first);
                continue;
            }
        }
        merged_.push_back(r);
    }
    marks_.clear();
    return merged_;
}

std::uint64_t DirtyRanges::element_count() {
    std::uint64_t n = 0;
    for (const Range& r : ranges()) n += r.count;
    return n;
}

void DirtyRanges::clear() noexcept {
    marks_.clear();
    merged_.clear();
}

// ---- RenderMesh ---------------------------------------------------------------------------

RenderMesh RenderMesh::build(const TriMesh& mesh, double growth) {
    RenderMesh r;
    r.rebuild(mesh, growth);
    return r;
}

void RenderMesh::rebuild(const TriMesh& m, double growth) {
    growth_ = std::max(growth, 1.0);
    const auto grow = [&](std::size_t n) {
        return static_cast<std::uint32_t>(std::ceil(static_cast<double>(n) * growth_)) + 64;
    };
    vertex_capacity_ = grow(m.n_vertices());
    face_capacity_ = grow(m.n_faces());
    body_of_vertex_.resize(vertex_capacity_, 0);
    vertex_count_ = static_cast<std::uint32_t>(m.n_vertices());
    face_count_ = static_cast<std::uint32_t>(m.n_faces());
    do {  // again with twice the cap region if the caps did not fit
        if (cap_overflow_) cap_min_ = 2 * cap_capacity_;
        cap_overflow_ = false;
        cap_capacity_ = std::max(cap_min_, vertex_capacity_ / 4);
        vertices_.assign(std::size_t{vertex_capacity_} + cap_capacity_, RenderVertex{});
        indices_.assign(std::size_t{face_capacity_} * 3, 0);
        cap_slot_of_face_.assign(face_capacity_, kNoSlot);
        cap_used_ = 0;
        for (std::uint32_t i = 0; i < vertex_count_; ++i) write_vertex(m, VertexHandle(int(i)));
        for (std::uint32_t f = 0; f < face_count_; ++f) write_face(m, FaceHandle(int(f)));
    } while (cap_overflow_);
    dirty_vertices_.clear();
    dirty_indices_.clear();
    dirty_vertices_.mark_range(0, vertex_capacity_ + cap_used_);
    dirty_indices_.mark_range(0, face_count_ * 3);
    needs_realloc_ = true;
    ++generation_;
}

MeshSyncStats RenderMesh::finish_sync(const TriMesh& m, MeshSyncStats s) {
    if (!cap_overflow_) return s;
    rebuild(m, growth_);  // a cap face found no corners left: more room, everything again
    s.rebuilt = true;
    s.vertices_written = vertex_count_;
    s.faces_written = face_count_;
    return s;
}

bool RenderMesh::rebuild_if_full(const TriMesh& m, MeshSyncStats& s) {
    if (fits(m)) return false;
    rebuild(m, growth_);
    s.rebuilt = true;
    s.vertices_written = vertex_count_;
    s.faces_written = face_count_;
    return true;
}

bool RenderMesh::fits(const TriMesh& m) const noexcept {
    return m.n_vertices() <= vertex_capacity_ && m.n_faces() <= face_capacity_;
}

void RenderMesh::write_vertex(const TriMesh& m, VertexHandle v) {
    const auto i = static_cast<std::uint32_t>(v.idx());
    RenderVertex r =
        make_vertex(m.point(v), m.normal(v), kind_of(m.data(v).material()), body_of_vertex_[i]);
    if (m.status(v).deleted()) r = RenderVertex{};
    if (same(r, vertices_[i])) return;
    vertices_[i] = r;
    dirty_vertices_.mark(i);
}

std::uint32_t RenderMesh::cap_slot(std::uint32_t face) {
    std::uint32_t& slot = cap_slot_of_face_[face];
    if (slot != kNoSlot) return slot;
    if (cap_used_ + 3 > cap_capacity_) {
        cap_overflow_ = true;  // drawn plain until finish_sync() rebuilds with more room
        return kNoSlot;
    }
    slot = vertex_capacity_ + cap_used_;
    cap_used_ += 3;
    return slot;
}

void RenderMesh::write_face(const TriMesh& m, FaceHandle f) {
    const auto fi = static_cast<std::uint32_t>(f.idx());
    std::uint32_t tri[3] = {0, 0, 0};
    if (!m.status(f).deleted()) {
        VertexHandle vs[3];
        int k = 0;
        for (VertexHandle v : m.fv_range(f)) vs[k++] = v;
        const std::uint32_t slot = is_cap(m, f) ? cap_slot(fi) : kNoSlot;
        if (slot == kNoSlot) {
            for (int i = 0; i < 3; ++i) tri[i] = static_cast<std::uint32_t>(vs[i].idx());
        } else {
            const auto &p0 = m.point(vs[0]), &p1 = m.point(vs[1]), &p2 = m.point(vs[2]);
            OpenMesh::Vec3d n = OpenMesh::cross(p1 - p0, p2 - p0);
            n = n.norm() > 0 ? n.normalized() : OpenMesh::Vec3d(0, 0, 1);
            OpenMesh::Vec3d u, v;
            plane_frame(n, u, v);
            for (int i = 0; i < 3; ++i) {
                const auto vi = static_cast<std::uint32_t>(vs[i].idx());
                RenderVertex r = make_vertex(
                    m.point(vs[i]), n, cut_kind_of(m.data(vs[i]).material()), body_of_vertex_[vi]);
                r.plane_uv[0] = static_cast<float>(OpenMesh::dot(m.point(vs[i]), u));
                r.plane_uv[1] = static_cast<float>(OpenMesh::dot(m.point(vs[i]), v));
                if (!same(r, vertices_[slot + i])) {
                    vertices_[slot + i] = r;
                    dirty_vertices_.mark(slot + i);
                }
                tri[i] = slot + i;
            }
        }
    }
    for (int i = 0; i < 3; ++i) {
        if (indices_[fi * 3 + i] != tri[i]) {
            indices_[fi * 3 + i] = tri[i];
            dirty_indices_.mark(fi * 3 + i);
        }
    }
}

MeshSyncStats RenderMesh::update_after_edit(const TriMesh& m, std::span<const VertexHandle> moved,
                                            std::span<const FaceHandle> touched) {
    MeshSyncStats s;
    if (rebuild_if_full(m, s)) return s;
    const auto old_vertices = vertex_count_;
    const auto old_faces = face_count_;
    vertex_count_ = static_cast<std::uint32_t>(m.n_vertices());
    face_count_ = static_cast<std::uint32_t>(m.n_faces());
    const auto face_done = [&](FaceHandle f) {
        write_face(m, f);
        ++s.faces_written;
    };
    for (std::uint32_t i = old_vertices; i < vertex_count_; ++i) {
        const VertexHandle v(static_cast<int>(i));
        write_vertex(m, v);
        ++s.vertices_written;
        if (m.status(v).deleted()) continue;
        for (FaceHandle f : m.vf_range(v))
            if (static_cast<std::uint32_t>(f.idx()) < old_faces) face_done(f);
    }
    for (std::uint32_t f = old_faces; f < face_count_; ++f) face_done(FaceHandle(int(f)));
    for (VertexHandle v : moved) {
        write_vertex(m, v);
        ++s.vertices_written;
        for (FaceHandle f : m.vf_range(v))
            if (cap_slot_of_face_[static_cast<std::uint32_t>(f.idx())] != kNoSlot) face_done(f);
    }
    for (FaceHandle f : touched) face_done(f);
    return finish_sync(m, s);
}

MeshSyncStats RenderMesh::update_all(const TriMesh& m) {
    MeshSyncStats s;
    if (rebuild_if_full(m, s)) return s;
    const auto old_faces = face_count_;
    vertex_count_ = static_cast<std::uint32_t>(m.n_vertices());
    face_count_ = static_cast<std::uint32_t>(m.n_faces());
    for (std::uint32_t i = 0; i < vertex_count_; ++i) write_vertex(m, VertexHandle(int(i)));
    for (std::uint32_t f = 0; f < face_count_; ++f) write_face(m, FaceHandle(int(f)));
    for (std::uint32_t f = face_count_; f < old_faces; ++f)  // faces gone after compaction
        for (int i = 0; i < 3; ++i) indices_[f * 3 + i] = 0;
    s.vertices_written = vertex_count_;
    s.faces_written = face_count_;
    return finish_sync(m, s);
}

void RenderMesh::write_vertex_and_caps(const TriMesh& m, VertexHandle v) {
    write_vertex(m, v);
    if (m.status(v).deleted()) return;
    for (FaceHandle f : m.vf_range(v))
        if (cap_slot_of_face_[static_cast<std::uint32_t>(f.idx())] != kNoSlot) write_face(m, f);
}

void RenderMesh::set_one_body(const TriMesh& m, VertexHandle v, std::uint8_t body) {
    std::uint8_t& b = body_of_vertex_[static_cast<std::uint32_t>(v.idx())];
    if (b == body) return;
    b = body;
    write_vertex_and_caps(m, v);
}

void RenderMesh::set_body(const TriMesh& m, std::span<const VertexHandle> vertices,
                          std::uint8_t body) {
    for (VertexHandle v : vertices) set_one_body(m, v, body < kMaxBodies ? body : 0);
}

MeshSyncStats RenderMesh::apply(const TriMesh& m, const cut::SessionChanges& changes) {
    if (changes.everything || !fits(m)) return update_all(m);
    MeshSyncStats s;
    vertex_count_ = static_cast<std::uint32_t>(m.n_vertices());
    face_count_ = static_cast<std::uint32_t>(m.n_faces());
    for (const cut::IndexRange& r : changes.vertices) {
        for (std::uint32_t i = r.first; i < r.first + r.count && i < vertex_count_; ++i) {
            write_vertex_and_caps(m, VertexHandle(static_cast<int>(i)));
            ++s.vertices_written;
        }
    }
    for (const cut::IndexRange& r : changes.faces) {
        for (std::uint32_t f = r.first; f < r.first + r.count && f < face_count_; ++f) {
            write_face(m, FaceHandle(static_cast<int>(f)));
            ++s.faces_written;
        }
    }
    return finish_sync(m, s);
}

}  // namespace kerf::render
