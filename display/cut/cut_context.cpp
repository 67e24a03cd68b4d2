#include "display/cut/cut_context.hpp"

#include <algorithm>

#include "display/cut/context_state.hpp"
#include "display/cut/cross_section.hpp"

namespace kerf::cut {

namespace detail {

ContextState::ContextState(mesh::TriMesh& m) : mesh(m) {
    mesh.add_property(v_stamp);
    mesh.add_property(v_node);
    mesh.add_property(e_stamp);
    mesh.add_property(e_node);
    mesh.add_property(f_stamp);
    if (!mesh.get_property_handle(cap, kCapFaceProperty)) mesh.add_property(cap, kCapFaceProperty);
    rebuild();
}

ContextState::~ContextState() {
    mesh.remove_property(v_stamp);
    mesh.remove_property(v_node);
    mesh.remove_property(e_stamp);
    mesh.remove_property(e_node);
    mesh.remove_property(f_stamp);
}

void ContextState::rebuild() {
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (auto v : mesh.vertices()) {
        lo.minimize(mesh.point(v));
        hi.maximize(mesh.point(v));
    }
    scale_m = mesh.n_vertices() == 0 ? 0.0 : (hi - lo).norm();
    tolerance_m = Plane::tolerance_for_scale(scale_m);
    max_edge_m = 0.0;
    for (auto e : mesh.edges()) {
        const auto h = mesh.halfedge_handle(e, 0);
        const auto f0 = mesh.face_handle(h),
                   f1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
        const bool cap_edge = (f0.is_valid() && mesh.property(cap, f0) != kCapNone) ||
                              (f1.is_valid() && mesh.property(cap, f1) != kCapNone);
        if (!cap_edge) max_edge_m = std::max(max_edge_m, mesh.calc_edge_length(e));
    }
    grid.build(mesh);
    cap_faces.clear();
    for (auto f : mesh.faces())
        if (mesh.property(cap, f) != kCapNone) cap_faces.push_back(f);
    for (auto v : mesh.all_vertices()) mesh.property(v_stamp, v) = 0;
    for (auto e : mesh.all_edges()) mesh.property(e_stamp, e) = 0;
    for (auto f : mesh.all_faces()) mesh.property(f_stamp, f) = 0;
    generation = 1;
    // Headroom for the cuts to come: as much again of everything, reserved and made resident
    // once here, so no cut reallocates or page-faults.
    reserved_vertices = 2 * mesh.n_vertices() + 4096;
    reserved_edges = 2 * mesh.n_edges() + 12288;
    reserved_faces = 2 * mesh.n_faces() + 8192;
    reserve_resident();
}

void ContextState::reserve_resident() {
    mesh.reserve(reserved_vertices, reserved_edges, reserved_faces);
    const std::size_t nv = mesh.n_vertices(), ne = mesh.n_edges(), nf = mesh.n_faces();
    // Every connectivity array and property grows into its capacity and shrinks back: std::vector
    // keeps the capacity, the kernel keeps the pages. Default construction writes nothing for
    // OpenMesh's vector types (points, normals), so every element of every property is also
    // written explicitly (a copy of element 0). Nothing observes the intermediate size.
    mesh.resize(reserved_vertices, reserved_edges, reserved_faces);
    auto write_each = [this](auto first, std::size_t from, std::size_t to) {
        using Handle = decltype(first);
        for (std::size_t i = from; i < to; ++i)
            mesh.copy_all_properties(first, Handle(static_cast<int>(i)), true);
    };
    if (nv > 0) write_each(mesh::VertexHandle(0), nv, reserved_vertices);
    if (ne > 0) {
        write_each(mesh::EdgeHandle(0), ne, reserved_edges);
        write_each(mesh::HalfedgeHandle(0), 2 * ne, 2 * reserved_edges);
    }
    if (nf > 0) write_each(mesh::FaceHandle(0), nf, reserved_faces);
    grid.reserve_resident(reserved_faces - nf);
    mesh.resize(nv, ne, nf);
}

void ContextState::ensure_capacity(std::size_t vertices, std::size_t edges, std::size_t faces) {
    const bool room = mesh.n_vertices() + vertices <= reserved_vertices &&
                      mesh.n_edges() + edges <= reserved_edges &&
                      mesh.n_faces() + faces <= reserved_faces;
    if (!room) grow(vertices, edges, faces);
}

void ContextState::grow(std::size_t vertices, std::size_t edges, std::size_t faces) {
    reserved_vertices = std::max(mesh.n_vertices() + vertices, 2 * reserved_vertices);
    reserved_edges = std::max(mesh.n_edges() + edges, 2 * reserved_edges);
    reserved_faces = std::max(mesh.n_faces() + faces, 2 * reserved_faces);
    reserve_resident();
}

void ContextState::next_generation() {
    if (++generation != 0) return;
    for (auto v : mesh.all_vertices()) mesh.property(v_stamp, v) = 0;
    for (auto e : mesh.all_edges()) mesh.property(e_stamp, e) = 0;
    for (auto f : mesh.all_faces()) mesh.property(f_stamp, f) = 0;
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
    state_->grid.widen(max_distance_m);
    state_->max_edge_m += 2.0 * max_distance_m;
}

void CutContext::rebuild() { state_->rebuild(); }

std::size_t CutContext::spare_faces() const noexcept {
    const std::size_t used = state_->mesh.n_faces();
    return state_->reserved_faces > used ? state_->reserved_faces - used : 0;
}

void CutContext::grow_capacity() { state_->grow(0, 0, 0); }

}  // namespace kerf::cut
