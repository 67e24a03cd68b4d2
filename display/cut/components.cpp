#include "display/cut/components.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace kerf::cut {
namespace {

inline bool live(const mesh::TriMesh& m, mesh::FaceHandle f) {
    return f.is_valid() && static_cast<std::size_t>(f.idx()) < m.n_faces() &&
           !(m.has_face_status() && m.status(f).deleted());
}

/// Calls `visit(g)` for every live face sharing an edge with f.
template <class Visit>
void for_each_neighbour(const mesh::TriMesh& m, mesh::FaceHandle f, Visit&& visit) {
    for (const auto h : m.fh_range(f)) {
        const auto g = m.opposite_face_handle(h);
        if (live(m, g)) visit(g);
    }
}

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

}  // namespace

Body make_body(const mesh::TriMesh& m, std::vector<mesh::FaceHandle> faces,
               std::vector<std::uint32_t>& vertex_seen, std::uint32_t stamp) {
    Body b;
    if (!std::is_sorted(faces.begin(), faces.end())) std::sort(faces.begin(), faces.end());
    b.faces = std::move(faces);
    // The sums in locals, not in `b` (whose vertex list grows in the loop, so the compiler kept
    // them in memory: a store and a load on every face's chain): the same operations in the same
    // order, so the same bits as Point::minimize / maximize and `volume_m3 +=` would give.
    double volume = 0.0;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    std::size_t first = vertex_seen.size(), last = 0;  // the range of the vertices stamped here
    for (const auto f : b.faces) {
        // The corners as fv_range() gives them (from the face's half-edge, following next),
        // straight from the half-edge arrays: a circulator costs several times more.
        const mesh::HalfedgeHandle h0 = m.halfedge_handle(f);
        const mesh::HalfedgeHandle h1 = m.next_halfedge_handle(h0);
        const mesh::HalfedgeHandle h2 = m.next_halfedge_handle(h1);
        const mesh::VertexHandle corner[3] = {m.to_vertex_handle(h0), m.to_vertex_handle(h1),
                                              m.to_vertex_handle(h2)};
        mesh::Point p[3];
        for (int k = 0; k < 3; ++k) {
            const auto v = corner[k];
            p[k] = m.point(v);
            const auto vi = static_cast<std::size_t>(v.idx());
            auto& seen = vertex_seen[vi];
            if (seen == stamp) continue;
            seen = stamp;
            first = std::min(first, vi);
            last = std::max(last, vi);
            b.vertices.push_back(v);
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[k][a]);
                hi[a] = std::max(hi[a], p[k][a]);
            }
        }
        volume += OpenMesh::dot(p[0], OpenMesh::cross(p[1], p[2])) / 6.0;
    }
    b.volume_m3 = volume;
    b.bbox_min_m = mesh::Point(lo[0], lo[1], lo[2]);
    b.bbox_max_m = mesh::Point(hi[0], hi[1], hi[2]);
    // The vertices in index order. A body's vertices usually lie together (a bone's in its
    // file): when their range is at most kScanWidth times their number, scan the stamps over it
    // instead of sorting, and keep the scan only if it found exactly the vertices stamped here
    // (a caller may have used the same stamp before).
    constexpr std::size_t kScanWidth = 4;
    const std::size_t n = b.vertices.size();
    if (n > 0 && last - first < kScanWidth * n) {
        std::vector<mesh::VertexHandle> in_order;
        in_order.reserve(n);
        for (std::size_t i = first; i <= last; ++i) {
            if (vertex_seen[i] == stamp) in_order.emplace_back(static_cast<int>(i));
        }
        if (in_order.size() == n) {
            b.vertices = std::move(in_order);
            return b;
        }
    }
    std::sort(b.vertices.begin(), b.vertices.end());
    return b;
}

std::vector<Body> find_components(const mesh::TriMesh& m) {
    // Faces joined through shared edges by union-find over the edge array (one pass in memory
    // order; a breadth-first search through circulators was most of this function on a 1M mesh),
    // each component's root its lowest face.
    const std::size_t nf = m.n_faces();
    // live(m, f) with the face count and the status array read once (n_faces() is a virtual
    // call): the same test.
    const OpenMesh::Attributes::StatusInfo* const face_status =
        m.has_face_status() ? m.property(m.face_status_pph()).data_vector().data() : nullptr;
    const auto is_live = [nf, face_status](mesh::FaceHandle f) {
        const int i = f.idx();
        return i >= 0 && static_cast<std::size_t>(i) < nf &&
               !(face_status != nullptr && face_status[i].deleted());
    };
    const OpenMesh::Attributes::StatusInfo* const edge_status =
        m.has_edge_status() ? m.property(m.edge_status_pph()).data_vector().data() : nullptr;
    std::vector<std::uint32_t> parent(nf);
    std::iota(parent.begin(), parent.end(), 0u);
    const std::size_t ne = m.n_edges();
    for (std::size_t e = 0; e < ne; ++e) {
        if (edge_status != nullptr && edge_status[e].deleted()) continue;
        const auto h = mesh::HalfedgeHandle(static_cast<int>(2 * e));
        const auto f0 = m.face_handle(h), f1 = m.face_handle(m.opposite_halfedge_handle(h));
        if (!is_live(f0) || !is_live(f1)) continue;
        const auto a = find_root(parent, static_cast<std::uint32_t>(f0.idx()));
        const auto b = find_root(parent, static_cast<std::uint32_t>(f1.idx()));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
    // Bodies in the order of their lowest face, each with its faces in index order.
    constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    std::vector<std::uint32_t> body_of_root(nf, kNone);
    std::vector<std::vector<mesh::FaceHandle>> faces;
    for (std::size_t i = 0; i < nf; ++i) {
        const mesh::FaceHandle f(static_cast<int>(i));
        if (!is_live(f)) continue;
        const std::uint32_t root = find_root(parent, static_cast<std::uint32_t>(i));
        if (body_of_root[root] == kNone) {
            body_of_root[root] = static_cast<std::uint32_t>(faces.size());
            faces.emplace_back();
        }
        faces[body_of_root[root]].push_back(f);
    }
    std::vector<std::uint32_t> vertex_seen(m.n_vertices(), 0);
    std::vector<Body> bodies;
    bodies.reserve(faces.size());
    for (auto& body_faces : faces) {
        const auto stamp = static_cast<std::uint32_t>(bodies.size() + 1);
        bodies.push_back(make_body(m, std::move(body_faces), vertex_seen, stamp));
    }
    return bodies;
}

namespace {

bool box_holds(const Body& outer, const Body& inner) {
    for (int k = 0; k < 3; ++k) {
        if (inner.bbox_min_m[k] < outer.bbox_min_m[k] ||
            inner.bbox_max_m[k] > outer.bbox_max_m[k]) {
            return false;
        }
    }
    return true;
}

/// Appends `cavity` to `into`; both lists are sorted (make_body), so a merge keeps them sorted.
void absorb(Body& into, const Body& cavity) {
    const auto merge = [](auto& into_list, const auto& from) {
        const auto middle = static_cast<std::ptrdiff_t>(into_list.size());
        into_list.insert(into_list.end(), from.begin(), from.end());
        std::inplace_merge(into_list.begin(), into_list.begin() + middle, into_list.end());
    };
    merge(into.faces, cavity.faces);
    merge(into.vertices, cavity.vertices);
    into.volume_m3 += cavity.volume_m3;
}

}  // namespace

std::vector<Body> group_cavities(std::vector<Body> shells) {
    std::vector<Body> bodies;
    std::vector<double> shell_volume;  // each body's own shell volume, before cavities
    for (Body& s : shells) {
        if (s.volume_m3 < 0) continue;
        shell_volume.push_back(s.volume_m3);
        bodies.push_back(std::move(s));  // its volume stays readable below (a double)
    }
    for (const Body& cavity : shells) {
        if (cavity.volume_m3 >= 0) continue;
        std::size_t best = bodies.size();
        for (std::size_t b = 0; b < bodies.size(); ++b) {
            if (b >= shell_volume.size() || !box_holds(bodies[b], cavity)) continue;
            if (best == bodies.size() || shell_volume[b] < shell_volume[best]) best = b;
        }
        if (best == bodies.size())
            bodies.push_back(cavity);
        else
            absorb(bodies[best], cavity);
    }
    return bodies;
}

PieceFinder::PieceFinder(const mesh::TriMesh& mesh) : mesh_(mesh) { grow_to_mesh(); }

void PieceFinder::grow_to_mesh() {
    // Growing only appends zeros for new elements: O(growth), no pass over the mesh.
    face_stamp_.resize(mesh_.n_faces(), 0);
    face_owner_.resize(mesh_.n_faces(), 0);
    vertex_stamp_.resize(mesh_.n_vertices(), 0);
}

bool PieceFinder::claimed(mesh::FaceHandle f) const noexcept {
    return face_stamp_[static_cast<std::size_t>(f.idx())] == stamp_;
}

namespace {

/// One breadth-first search of the lockstep.
struct Search {
    std::vector<mesh::FaceHandle> faces;  // claimed, in claim order; [head, end) is the frontier
    std::size_t head = 0;
    bool growing() const noexcept { return head < faces.size(); }
};

}  // namespace

SeverReport PieceFinder::find_pieces(std::span<const mesh::FaceHandle> seeds,
                                     std::span<const Glue> glue) {
    grow_to_mesh();
    if (++stamp_ == 0) {  // wrapped: forget every old stamp once in 2^32 calls
        std::fill(face_stamp_.begin(), face_stamp_.end(), 0);
        std::fill(vertex_stamp_.begin(), vertex_stamp_.end(), 0);
        stamp_ = 1;
    }
    const auto n = static_cast<std::uint32_t>(seeds.size());
    std::vector<Search> search(n);
    std::vector<std::uint32_t> group(n);
    std::iota(group.begin(), group.end(), 0u);
    SeverReport report;
    report.piece_of_seed.assign(n, SeverReport::kRemainder);
    std::vector<std::uint8_t> closed(n, 0);  // per group root: already reported
    for (std::uint32_t s = 0; s < n; ++s) {
        const auto f = seeds[s];
        if (!live(mesh_, f)) {
            closed[s] = 1;  // an invalid seed takes no part
            continue;
        }
        if (claimed(f)) {
            const auto a = find_root(group, s);
            const auto b = find_root(group, face_owner_[static_cast<std::size_t>(f.idx())]);
            group[std::max(a, b)] = std::min(a, b);
            continue;
        }
        face_stamp_[static_cast<std::size_t>(f.idx())] = stamp_;
        face_owner_[static_cast<std::size_t>(f.idx())] = s;
        search[s].faces.push_back(f);
    }
    auto step = [&](std::uint32_t s) {
        const auto f = search[s].faces[search[s].head++];
        ++report.faces_visited;
        auto reach = [&](mesh::FaceHandle g) {
            const auto gi = static_cast<std::size_t>(g.idx());
            if (face_stamp_[gi] != stamp_) {
                face_stamp_[gi] = stamp_;
                face_owner_[gi] = s;
                search[s].faces.push_back(g);
                return;
            }
            const auto a = find_root(group, s);
            const auto b = find_root(group, face_owner_[gi]);
            if (a != b) group[std::max(a, b)] = std::min(a, b);
        };
        for_each_neighbour(mesh_, f, reach);
        if (glue.empty()) return;
        for (const auto v : mesh_.fv_range(f)) {
            const Glue lo{v, mesh::VertexHandle()};
            auto it = std::lower_bound(glue.begin(), glue.end(), lo);
            for (; it != glue.end() && it->a == v; ++it)
                for (const auto g : mesh_.vf_range(it->b))
                    if (live(mesh_, g)) reach(g);
        }
    };
    std::vector<std::uint8_t> open(n, 0);
    for (;;) {
        // Groups: a root with any growing member is open; an open group with none is closed now.
        std::fill(open.begin(), open.end(), 0);
        for (std::uint32_t s = 0; s < n; ++s) {
            if (search[s].growing()) open[find_root(group, s)] = 1;
        }
        std::uint32_t open_groups = 0;
        for (std::uint32_t r = 0; r < n; ++r) {
            if (find_root(group, r) != r || closed[r] != 0) continue;
            if (open[r] != 0) {
                ++open_groups;
                continue;
            }
            closed[r] = 1;  // walked whole: a piece of its own
            std::vector<mesh::FaceHandle> faces;
            for (std::uint32_t s = 0; s < n; ++s) {
                if (find_root(group, s) != r) continue;
                faces.insert(faces.end(), search[s].faces.begin(), search[s].faces.end());
                report.piece_of_seed[s] = static_cast<std::uint32_t>(report.severed.size());
            }
            report.severed.push_back(make_body(mesh_, std::move(faces), vertex_stamp_, stamp_));
        }
        if (open_groups <= 1) break;
        for (std::uint32_t s = 0; s < n; ++s) {
            if (search[s].growing()) step(s);
        }
    }
    return report;
}

SeverReport PieceFinder::find_pieces(const CrossSection& cut, std::span<const Glue> glue) {
    std::vector<mesh::FaceHandle> seeds;
    for (const CrossSectionSide* side : {&cut.positive, &cut.negative}) {
        for (const auto& loop : side->loops) {
            if (loop.empty() || !loop.front().is_valid()) continue;
            for (const auto f : mesh_.vf_range(loop.front())) {
                seeds.push_back(f);
                break;
            }
        }
    }
    return find_pieces(seeds, glue);
}

}  // namespace kerf::cut
