#include "display/cut/cut_context.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "config/base/length_unit.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/cross_section.hpp"
#include "display/mesh/indexed_mesh.hpp"

namespace kerf::cut {

namespace detail {

namespace {

/// Pending face-tree inserts hung on their leaves per idle step (all of them: a few ms at most).
constexpr std::size_t kFlushStep = FaceTree::kPendingFaces;

// Element kinds grown one at a time by grow_step().
enum class Kind { kVertices, kEdges, kFaces, kTree };
constexpr int kKinds = 4;

}  // namespace

ContextState::ContextState(mesh::TriMesh& m) : mesh(m) {
    if (!mesh.get_property_handle(cap, kCapFaceProperty)) mesh.add_property(cap, kCapFaceProperty);
    index();
    // The stamps after the face tree: their 7 MB (1M-face mesh) then reuse the heap memory the
    // tree's scratch boxes left, instead of 1,700 pages first touched (4 ms here). add_property
    // writes every stamp 0 (value-initialised) and the generation is 1: no clear_stamps().
    mesh.add_property(v_stamp);
    mesh.add_property(e_stamp);
    mesh.add_property(f_stamp);
    reserve_headroom();
}

ContextState::~ContextState() {
    mesh.remove_property(v_stamp);
    mesh.remove_property(e_stamp);
    mesh.remove_property(f_stamp);
}

bool ContextState::degenerate_in_a_float_file(const Vec3& a, const Vec3& b, const Vec3& c,
                                              double floor_m2) {
    for (const LengthUnit u : {LengthUnit::kMetre, LengthUnit::kMillimetre, LengthUnit::kCentimetre,
                               LengthUnit::kInch, LengthUnit::kMicrometre}) {
        const double unit = metres_per_unit(u);
        // Through a volatile float: gcc 12 -O2 vectorises (double)(float)(x) on two lanes of an
        // OpenMesh vector and drops the rounding (seen in this function; clang keeps it).
        auto f32 = [](double x) -> double {
            volatile float f = static_cast<float>(x);
            return f;
        };
        auto written = [&](const Vec3& p) {
            return Vec3(f32(p[0] / unit), f32(p[1] / unit), f32(p[2] / unit));
        };
        const Vec3 fa = written(a), fb = written(b), fc = written(c);
        if (!(OpenMesh::cross(fb - fa, fc - fa).norm() * unit * unit > floor_m2)) return true;
    }
    return false;
}

void ContextState::rebuild() {
    index();
    clear_stamps();
    reserve_headroom();
}

void ContextState::index() {
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    const auto nv = static_cast<int>(mesh.n_vertices());
    const mesh::TriMesh::Point* points = mesh.points();
    const OpenMesh::Attributes::StatusInfo* const vertex_status =
        mesh.property(mesh.vertex_status_pph()).data_vector().data();
    for (int i = 0; i < nv; ++i) {
        if (vertex_status[i].deleted()) continue;
        minimize(lo, points[i]);  // Vec3::minimize written out (vec_ops.hpp)
        maximize(hi, points[i]);
    }
    scale_m = mesh.n_vertices() == 0 ? 0.0 : (hi - lo).norm();
    tolerance_m = Plane::tolerance_for_scale(scale_m);
    double reach = 0.0;  // the largest coordinate magnitude
    if (mesh.n_vertices() != 0)
        for (int a = 0; a < 3; ++a) reach = std::max({reach, std::abs(lo[a]), std::abs(hi[a])});
    float_rounding_m = std::ldexp(reach, -24);
    // The longest non-cap edge: measured by the tree's pass over the faces, or else here.
    double max_edge_sq = tree.build(mesh, mesh.property(cap).data_vector().data());
    if (max_edge_sq < 0.0) {
        max_edge_sq = 0.0;
        for (auto e : mesh.edges()) {
            const auto h = mesh.halfedge_handle(e, 0);
            const auto f0 = mesh.face_handle(h),
                       f1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
            const bool cap_edge = (f0.is_valid() && mesh.property(cap, f0) != kCapNone) ||
                                  (f1.is_valid() && mesh.property(cap, f1) != kCapNone);
            if (cap_edge) continue;
            const Vec3 d =
                points[mesh.to_vertex_handle(h).idx()] - points[mesh.from_vertex_handle(h).idx()];
            max_edge_sq = std::max(max_edge_sq, d.sqrnorm());
        }
    }
    max_edge_m = std::sqrt(max_edge_sq);
    // The cap faces in order, from the tag array (a face's status is read only where it is one).
    cap_faces.clear();
    const std::vector<std::uint8_t>& tags = mesh.property(cap).data_vector();
    const auto is_cap = [](std::uint8_t t) { return t != kCapNone; };
    for (auto at = std::find_if(tags.begin(), tags.end(), is_cap); at != tags.end();
         at = std::find_if(at + 1, tags.end(), is_cap)) {
        const mesh::FaceHandle f(static_cast<int>(at - tags.begin()));
        if (!mesh.status(f).deleted()) cap_faces.push_back(f);
    }
}

namespace {

// Writes every element array of `mesh` from its size up to `vertices`, `edges`, `faces` (within
// the reserved capacity) and shrinks back, so that those elements' pages are resident and their
// lines in cache: value-initialised elements are written by resize, the vector types (which
// default construction leaves unwritten) explicitly; std::vector keeps the capacity, the kernel
// keeps the pages.
void write_beyond(mesh::TriMesh& mesh, std::size_t vertices, std::size_t edges, std::size_t faces) {
    const std::size_t nv = mesh.n_vertices(), ne = mesh.n_edges(), nf = mesh.n_faces();
    auto write_tail = [&mesh](auto handle, std::size_t from) {
        auto& v = mesh.property(handle).data_vector();
        std::fill(v.begin() + static_cast<std::ptrdiff_t>(from), v.end(),
                  typename std::decay_t<decltype(v)>::value_type());
    };
    mesh.resize(vertices, edges, faces);
    write_tail(mesh.points_pph(), nv);
    write_tail(mesh.vertex_normals_pph(), nv);
    write_tail(mesh.vertex_texcoords2D_pph(), nv);
    write_tail(mesh.vertex_colors_pph(), nv);
    write_tail(mesh.face_normals_pph(), nf);
    mesh.resize(nv, ne, nf);
}

}  // namespace

void ContextState::reserve_headroom() {
    // Room for the cuts to come, reserved now (no cut reallocates); the first idle steps write
    // it (grow_step), so that no cut page-faults either.
    const std::size_t hf = headroom_faces(0);
    reserved_vertices = mesh.n_vertices() + hf / 2;
    reserved_edges = mesh.n_edges() + 2 * hf;
    reserved_faces = mesh.n_faces() + hf;
    mesh.reserve(reserved_vertices, reserved_edges, reserved_faces);
    cap_faces.reserve(cap_faces.size() + hf);
    tree.reserve(hf);
    unwritten_kinds = (1u << kKinds) - 1;
    // The first warm_appends() (after the first cut) warms what that cut adds, not the mesh.
    warmed_vertices = mesh.n_vertices(), warmed_edges = mesh.n_edges(),
    warmed_faces = mesh.n_faces();
}

std::size_t ContextState::headroom_faces(std::size_t min_spare_faces) const {
    // What mesh::load_mesh_owned() reserves, so growing into it copies nothing.
    return std::max(min_spare_faces, mesh::edit_headroom_faces(mesh.n_faces()));
}

bool ContextState::grow_step(std::size_t min_spare_faces) {
    if (generation > std::numeric_limits<Stamp>::max() - kStampReserve) {
        clear_stamps();
        return true;
    }
    if (tree.pending() > 0) {
        tree.flush_pending(kFlushStep);
        return true;
    }
    if (unwritten_kinds != 0) {
        const int k = std::countr_zero(unwritten_kinds);
        write_headroom(k);
        return true;
    }
    if (grow_kind(min_spare_faces)) return true;
    if (mesh.n_vertices() == warmed_vertices && mesh.n_edges() == warmed_edges &&
        mesh.n_faces() == warmed_faces)
        return false;
    warm_appends();
    return true;
}

void ContextState::warm_appends() {
    const std::size_t nv = mesh.n_vertices(), ne = mesh.n_edges(), nf = mesh.n_faces();
    // Twice the growth since the last warm (0 after a shrink, as after an undone edit).
    auto ahead = [](std::size_t n, std::size_t last, std::size_t reserved) {
        const std::size_t grown = n > last ? n - last : 0;
        return std::min(std::max(n, reserved), n + std::max(2 * grown, kWarmElements));
    };
    const std::size_t wv = ahead(nv, warmed_vertices, reserved_vertices);
    const std::size_t we = ahead(ne, warmed_edges, reserved_edges);
    const std::size_t wf = ahead(nf, warmed_faces, reserved_faces);
    write_beyond(mesh, wv, we, wf);
    // And the list of cap faces, which every cut appends to as well.
    const std::size_t caps = cap_faces.size();
    cap_faces.resize(std::min(cap_faces.capacity(), caps + (wf - nf)));
    cap_faces.resize(caps);
    warmed_vertices = nv, warmed_edges = ne, warmed_faces = nf;
}

void ContextState::write_headroom(int kind) {
    const std::size_t nv = mesh.n_vertices(), ne = mesh.n_edges(), nf = mesh.n_faces();
    switch (static_cast<Kind>(kind)) {
        case Kind::kVertices:
            write_beyond(mesh, std::max(nv, reserved_vertices), ne, nf);
            break;
        case Kind::kEdges:
            write_beyond(mesh, nv, std::max(ne, reserved_edges), nf);
            break;
        case Kind::kFaces:
            write_beyond(mesh, nv, ne, std::max(nf, reserved_faces));
            break;
        case Kind::kTree:
            tree.make_resident();
            break;
    }
    unwritten_kinds &= ~(1u << kind);
}

bool ContextState::grow_kind(std::size_t min_spare_faces) {
    const std::size_t hf = headroom_faces(min_spare_faces);
    const std::size_t nv = mesh.n_vertices(), ne = mesh.n_edges(), nf = mesh.n_faces();
    const std::size_t want[4] = {nv + hf / 2, ne + 2 * hf, nf + hf, hf};
    const std::size_t have[4] = {reserved_vertices, reserved_edges, reserved_faces,
                                 tree.spare_inserts()};
    const std::size_t used[4] = {nv, ne, nf, 0};
    for (int k = 0; k < kKinds; ++k) {
        // Grow a kind whose spare room fell below half its target headroom: reserve, then write.
        const std::size_t target_spare = want[k] - used[k];
        if (have[k] >= used[k] + target_spare / 2) continue;
        switch (static_cast<Kind>(k)) {
            case Kind::kVertices:
                mesh.reserve(want[k], ne, nf);
                reserved_vertices = want[k];
                break;
            case Kind::kEdges:
                mesh.reserve(nv, want[k], nf);
                reserved_edges = want[k];
                break;
            case Kind::kFaces:
                mesh.reserve(nv, ne, want[k]);
                cap_faces.reserve(cap_faces.size() + hf);
                reserved_faces = want[k];
                break;
            case Kind::kTree:
                tree.reserve(hf);
                break;
        }
        write_headroom(k);
        return true;
    }
    return false;
}

void ContextState::ensure_capacity(std::size_t vertices, std::size_t edges, std::size_t faces) {
    const bool room = mesh.n_vertices() + vertices <= reserved_vertices &&
                      mesh.n_edges() + edges <= reserved_edges &&
                      mesh.n_faces() + faces <= reserved_faces && faces <= tree.spare_inserts() &&
                      cap_faces.size() + faces <= cap_faces.capacity();
    if (room) return;
    ++growths_in_cuts;
    const std::size_t need = std::max({vertices, edges, faces});
    while (grow_kind(need)) {
    }
}

void ContextState::next_generation() {
    if (++generation != 0) return;
    clear_stamps();
}

void ContextState::clear_stamps() {
    std::fill_n(&mesh.property(v_stamp).data_vector()[0], mesh.n_vertices(), Stamp{0});
    std::fill_n(&mesh.property(e_stamp).data_vector()[0], mesh.n_edges(), Stamp{0});
    std::fill_n(&mesh.property(f_stamp).data_vector()[0], mesh.n_faces(), Stamp{0});
    generation = 1;
}

}  // namespace detail

CutContext::CutContext(mesh::TriMesh& mesh)
    : state_(std::make_unique<detail::ContextState>(mesh)) {}
CutContext::~CutContext() = default;

mesh::TriMesh& CutContext::mesh() noexcept { return state_->mesh; }
double CutContext::scale_m() const noexcept { return state_->scale_m; }
double CutContext::tolerance_m() const noexcept { return state_->tolerance_m; }

void CutContext::note_vertices_moved(double max_distance_m) noexcept {
    if (!(max_distance_m > 0.0)) return;
    state_->tree.widen(max_distance_m);
    state_->max_edge_m += 2.0 * max_distance_m;
}

void CutContext::rebuild() { state_->rebuild(); }

std::size_t CutContext::spare_faces() const noexcept {
    const std::size_t used = state_->mesh.n_faces();
    return state_->reserved_faces > used ? state_->reserved_faces - used : 0;
}

bool CutContext::grow_step(std::size_t min_spare_faces) {
    return state_->grow_step(min_spare_faces);
}

void CutContext::grow_capacity(std::size_t min_spare_faces) {
    while (state_->grow_step(min_spare_faces)) {
    }
}

std::uint64_t CutContext::growths_in_cuts() const noexcept { return state_->growths_in_cuts; }

}  // namespace kerf::cut
