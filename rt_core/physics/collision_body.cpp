// The chunked AABB tree behind CollisionBody (see collision_body.hpp for the design).
#include "rt_core/physics/collision_body.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include "rt_core/physics/triangle_geometry.hpp"

namespace kerf::physics {

namespace {

/// A tree node: a box (inflated by a hair so rounding never rejects a touching query) and either
/// two children at [first, first + 1] (count == 0) or `count` items from `first` (a leaf).
struct Node {
    float lo[3], hi[3];
    std::uint32_t first;
    std::uint32_t count;
};
static_assert(sizeof(Node) == 32);

/// A triangle's corners in leaf order, with its mesh index.
struct Tri {
    float v[9];
    std::uint32_t id;
};

struct Box {
    float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                   std::numeric_limits<float>::max()};
    float hi[3] = {-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                   -std::numeric_limits<float>::max()};
    void grow(const float* p) noexcept {
        for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
    }
    void grow(const Box& b) noexcept {
        grow(b.lo);
        grow(b.hi);
    }
};

void store_box(Node& n, const Box& b) noexcept {
    for (int i = 0; i < 3; ++i) {
        const float pad_lo = std::abs(b.lo[i]) * 1e-6f + 1e-9f;
        const float pad_hi = std::abs(b.hi[i]) * 1e-6f + 1e-9f;
        n.lo[i] = b.lo[i] - pad_lo;
        n.hi[i] = b.hi[i] + pad_hi;
    }
}

/// Half the perimeter of a node's box (the sum of its extents), m.
double half_perimeter(const Node& n) noexcept {
    return double(n.hi[0]) - n.lo[0] + double(n.hi[1]) - n.lo[1] + double(n.hi[2]) - n.lo[2];
}

/// An item to partition: its centre (3 floats) and its index.
struct Item {
    float c[3];
    std::uint32_t id;
};

/// Splits `items` at the median of the widest centre extent, recursively, until a range holds at
/// most `max_leaf` items; reorders `items` so every leaf is a contiguous range. Returns the nodes
/// (boxes unset): leaves have count > 0 and `first` into `items`, inner nodes their children at
/// [first, first + 1], always after their parent.
std::vector<Node> split_tree(std::span<Item> items, std::uint32_t max_leaf) {
    std::vector<Node> nodes;
    nodes.reserve(2 * (items.size() / std::max<std::uint32_t>(1, max_leaf)) + 2);
    struct Job {
        std::uint32_t node, begin, end;
    };
    std::vector<Job> jobs{{0, 0, static_cast<std::uint32_t>(items.size())}};
    nodes.push_back({});
    while (!jobs.empty()) {
        const Job job = jobs.back();
        jobs.pop_back();
        Box centres;  // in locals: Box::grow through a pointer would store every step (aliasing)
        float lo[3] = {centres.lo[0], centres.lo[1], centres.lo[2]};
        float hi[3] = {centres.hi[0], centres.hi[1], centres.hi[2]};
        for (std::uint32_t i = job.begin; i < job.end; ++i) {
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], items[i].c[a]), hi[a] = std::max(hi[a], items[i].c[a]);
            }
        }
        std::copy(lo, lo + 3, centres.lo), std::copy(hi, hi + 3, centres.hi);
        const std::uint32_t count = job.end - job.begin;
        int axis = 0;
        for (int i = 1; i < 3; ++i) {
            if (centres.hi[i] - centres.lo[i] > centres.hi[axis] - centres.lo[axis]) axis = i;
        }
        if (count <= max_leaf || !(centres.hi[axis] > centres.lo[axis])) {
            nodes[job.node].first = job.begin;
            nodes[job.node].count = count;
            continue;
        }
        const std::uint32_t mid = job.begin + count / 2;
        std::nth_element(items.begin() + job.begin, items.begin() + mid, items.begin() + job.end,
                         [axis](const Item& a, const Item& b) { return a.c[axis] < b.c[axis]; });
        const auto left = static_cast<std::uint32_t>(nodes.size());
        nodes.push_back({});
        nodes.push_back({});
        nodes[job.node].first = left;
        nodes[job.node].count = 0;
        jobs.push_back({left, job.begin, mid});
        jobs.push_back({left + 1, mid, job.end});
    }
    return nodes;
}

/// Sets the boxes of `nodes` bottom-up: a leaf's from `leaf_box(node)`, an inner node's from its
/// children (which follow it in the array); only those of leaves for which `stale(leaf)` holds and
/// of their ancestors (the others are kept as they are).
template <class LeafBox, class Stale>
void fit_boxes(std::vector<Node>& nodes, const LeafBox& leaf_box, const Stale& stale) {
    std::vector<std::uint8_t> refit(nodes.size(), 0);
    for (std::size_t n = nodes.size(); n-- > 0;) {
        Node& node = nodes[n];
        refit[n] = node.count > 0 ? stale(node) : refit[node.first] | refit[node.first + 1];
        if (!refit[n]) continue;
        Box box;
        if (node.count > 0) {
            box = leaf_box(node);
        } else {
            for (std::uint32_t c = node.first; c < node.first + 2; ++c) {
                box.grow(nodes[c].lo);
                box.grow(nodes[c].hi);
            }
        }
        store_box(node, box);
    }
}

/// Sets every box of `nodes` bottom-up (fit_boxes with every leaf stale).
template <class LeafBox>
void fit_boxes(std::vector<Node>& nodes, const LeafBox& leaf_box) {
    fit_boxes(nodes, leaf_box, [](const Node&) -> std::uint8_t { return 1; });
}

/// One chunk: its own tree over its triangles' corners. A triangle with an edge longer than
/// BuildOptions::max_piece_edge_m is indexed as pieces (piece_box: the box of each entry's piece;
/// empty when the chunk has none): one entry per piece, each with the whole triangle's corners,
/// so queries stay exact on the triangle and a long cap triangle does not give one box that every
/// query near the cut enters.
struct Chunk {
    std::vector<Node> nodes;
    std::vector<Tri> tris;
    std::vector<Box> piece_box;

    bool has_pieces() const noexcept { return !piece_box.empty(); }
    /// Refits the boxes: all of them, or those over a triangle flagged in `changed` (per mesh
    /// triangle) when given.
    void fit(const std::uint8_t* changed = nullptr) {
        const auto leaf_box = [&](const Node& leaf) {
            Box box;
            for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                if (has_pieces()) {
                    box.grow(piece_box[i]);
                } else {
                    for (int k = 0; k < 3; ++k) box.grow(&tris[i].v[3 * k]);
                }
            }
            return box;
        };
        if (!changed) return fit_boxes(nodes, leaf_box);
        fit_boxes(nodes, leaf_box, [&](const Node& leaf) {
            std::uint8_t stale = 0;
            for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                stale |= changed[tris[i].id];
            }
            return stale;
        });
    }
};

constexpr int kMaxPieces = 16;  ///< pieces per triangle at most

/// `x` rounded to float downwards (`up` false) or upwards.
float round_outward(double x, bool up) noexcept {
    const float f = static_cast<float>(x);
    if (up) return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

/// Covers triangle `v` (9 floats) with boxes, calling `piece(box, split)` for each: the
/// triangle's own box (split false) unless it is wider than `max_extent` on some axis; then,
/// while one is wider (and there are fewer than kMaxPieces), the widest box is halved across its
/// widest axis and the part of the triangle in it clipped to each half (split true). The boxes
/// (rounded outward to float) hold the whole triangle, which is all a query's box test needs. A
/// sliver 20 mm long gets about five 4 mm boxes whatever its direction (halving its longest
/// edge needs two splits per halving of its length).
template <class Piece>
void split_long(const float* v, double max_extent, const Piece& piece) {
    Box whole;
    for (int k = 0; k < 3; ++k) whole.grow(&v[3 * k]);
    if (!(std::max({whole.hi[0] - whole.lo[0], whole.hi[1] - whole.lo[1],
                    whole.hi[2] - whole.lo[2]}) > max_extent)) {
        piece(whole, false);
        return;
    }
    constexpr int kMaxCorners = 3 + kMaxPieces;  // a clip adds at most one corner
    struct Part {
        double c[kMaxCorners][3];
        int n = 0;
        double lo[3], hi[3];
        int axis = 0;
        double width = 0;  // along `axis`, the box's widest
        void measure() noexcept {
            for (int i = 0; i < 3; ++i) lo[i] = hi[i] = c[0][i];
            for (int k = 1; k < n; ++k) {
                for (int i = 0; i < 3; ++i)
                    lo[i] = std::min(lo[i], c[k][i]), hi[i] = std::max(hi[i], c[k][i]);
            }
            axis = 0;
            for (int i = 1; i < 3; ++i) {
                if (hi[i] - lo[i] > hi[axis] - lo[axis]) axis = i;
            }
            width = hi[axis] - lo[axis];
        }
    };
    Part parts[kMaxPieces];
    Part below;
    int count = 1;
    parts[0].n = 3;
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) parts[0].c[k][i] = v[3 * k + i];
    }
    parts[0].measure();
    while (count < kMaxPieces) {
        int widest = 0;
        for (int p = 1; p < count; ++p) {
            if (parts[p].width > parts[widest].width) widest = p;
        }
        const Part& part = parts[widest];
        if (!(part.width > max_extent)) break;
        // Clip the convex polygon at x[axis] = cut into the parts below and above.
        const int axis = part.axis;
        const double cut = 0.5 * (part.lo[axis] + part.hi[axis]);
        Part& above = parts[count++];
        below.n = above.n = 0;
        for (int k = 0; k < part.n; ++k) {
            const double* a = part.c[k];
            const double* b = part.c[k + 1 == part.n ? 0 : k + 1];  // no division
            if (a[axis] <= cut) std::copy(a, a + 3, below.c[below.n++]);
            if (a[axis] >= cut) std::copy(a, a + 3, above.c[above.n++]);
            if ((a[axis] < cut && b[axis] > cut) || (a[axis] > cut && b[axis] < cut)) {
                const double t = (cut - a[axis]) / (b[axis] - a[axis]);
                double x[3];
                for (int i = 0; i < 3; ++i) x[i] = a[i] + t * (b[i] - a[i]);
                x[axis] = cut;
                std::copy(x, x + 3, below.c[below.n++]);
                std::copy(x, x + 3, above.c[above.n++]);
            }
        }
        below.measure();
        above.measure();
        parts[widest] = below;
    }
    for (int p = 0; p < count; ++p) {
        Box box;
        for (int i = 0; i < 3; ++i) {
            box.lo[i] = round_outward(parts[p].lo[i], false);
            box.hi[i] = round_outward(parts[p].hi[i], true);
        }
        piece(box, count > 1);
    }
}

constexpr int kStackSize = 128;  ///< > 2 x (top depth + chunk depth) for 2^26 triangles

}  // namespace

struct CollisionBody::Impl {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::vector<Material> materials;
    std::vector<std::uint32_t> chunk_of;               ///< per triangle: its chunk's slot
    std::vector<std::shared_ptr<const Chunk>> chunks;  ///< slots; empty slots are null
    std::vector<Node> top;               ///< tree over the chunks; leaves index top_ids
    std::vector<std::uint32_t> top_ids;  ///< chunk slots in top-leaf order
    RigidTransform pose;
    BuildOptions options;

    const float* corner(std::uint32_t tri, int k) const noexcept {
        return &positions[3 * std::size_t{indices[3 * std::size_t{tri} + k]}];
    }
    Item item(std::uint32_t tri) const noexcept {
        Item it{{0, 0, 0}, tri};
        for (int k = 0; k < 3; ++k) {
            const float* p = corner(tri, k);
            for (int a = 0; a < 3; ++a) it.c[a] += p[a];
        }
        return it;
    }
    std::shared_ptr<const Chunk> build_chunk(std::span<Item> items) const;
    /// The distinct triangles of `chunk` with an index below `limit`, as items (corners re-read).
    std::vector<Item> triangles_of(const Chunk& chunk, std::uint32_t limit) const;
    /// `old` refitted to this mesh; `changed` (optional, per triangle of `old`): which to re-read.
    std::shared_ptr<const Chunk> refit_chunk(const Chunk& old,
                                             const std::uint8_t* changed = nullptr) const;
    void add_chunks(std::vector<Item> items, std::uint32_t group_triangles);
    void build_top();
};

std::shared_ptr<const Chunk> CollisionBody::Impl::build_chunk(std::span<Item> items) const {
    auto chunk = std::make_shared<Chunk>();
    // Entries: the triangles, long ones as pieces. Item ids index `entry_tri` while partitioning.
    std::vector<Item> entries;
    std::vector<std::uint32_t> entry_tri;
    std::vector<Box> entry_box;
    entries.reserve(items.size());
    entry_tri.reserve(items.size());
    entry_box.reserve(items.size());
    for (const Item& it : items) {
        float v[9];
        for (int k = 0; k < 3; ++k) std::memcpy(&v[3 * k], corner(it.id, k), 12);
        split_long(v, options.max_piece_edge_m, [&](const Box& box, bool split) {
            Item e = it;
            if (split) {
                for (int a = 0; a < 3; ++a) e.c[a] = 1.5f * (box.lo[a] + box.hi[a]);
            }
            e.id = static_cast<std::uint32_t>(entry_tri.size());
            entries.push_back(e);
            entry_tri.push_back(it.id);
            entry_box.push_back(box);
        });
    }
    const bool pieces = entries.size() != items.size();
    chunk->nodes = split_tree(entries, options.leaf_triangles);
    chunk->tris.resize(entries.size());
    if (pieces) chunk->piece_box.resize(entries.size());
    for (std::size_t i = 0; i < entries.size(); ++i) {
        Tri& tri = chunk->tris[i];
        tri.id = entry_tri[entries[i].id];
        for (int k = 0; k < 3; ++k) std::memcpy(&tri.v[3 * k], corner(tri.id, k), 12);
        if (pieces) chunk->piece_box[i] = entry_box[entries[i].id];
    }
    chunk->fit();
    return chunk;
}

/// A copy of `old` with its triangles' corners re-read (only those flagged in `changed`, per
/// triangle, when given) and every box refitted (a chunk with pieces is rebuilt: its triangles'
/// pieces follow their new corners).
std::shared_ptr<const Chunk> CollisionBody::Impl::refit_chunk(const Chunk& old,
                                                              const std::uint8_t* changed) const {
    if (old.has_pieces()) {
        std::vector<Item> items = triangles_of(old, std::numeric_limits<std::uint32_t>::max());
        return build_chunk(items);
    }
    auto chunk = std::make_shared<Chunk>(old);
    for (Tri& tri : chunk->tris) {
        if (changed && !changed[tri.id]) continue;
        for (int k = 0; k < 3; ++k) std::memcpy(&tri.v[3 * k], corner(tri.id, k), 12);
    }
    chunk->fit(changed);
    return chunk;
}

std::vector<Item> CollisionBody::Impl::triangles_of(const Chunk& chunk, std::uint32_t limit) const {
    std::vector<std::uint32_t> ids;
    ids.reserve(chunk.tris.size());
    for (const Tri& tri : chunk.tris) {
        if (tri.id < limit) ids.push_back(tri.id);
    }
    if (chunk.has_pieces()) {
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    }
    std::vector<Item> items;
    items.reserve(ids.size());
    for (std::uint32_t id : ids) items.push_back(item(id));
    return items;
}

/// Splits `items` spatially into groups of at most `group_triangles`, each a new chunk slot.
void CollisionBody::Impl::add_chunks(std::vector<Item> items, std::uint32_t group_triangles) {
    if (items.empty()) return;
    const std::vector<Node> groups = split_tree(items, std::max<std::uint32_t>(group_triangles, 1));
    for (const Node& g : groups) {
        if (g.count == 0) continue;
        const auto slot = static_cast<std::uint32_t>(chunks.size());
        const std::span<Item> members(items.data() + g.first, g.count);
        for (const Item& it : members) chunk_of[it.id] = slot;
        chunks.push_back(build_chunk(members));
    }
}

void CollisionBody::Impl::build_top() {
    std::vector<Item> items;
    for (std::uint32_t c = 0; c < chunks.size(); ++c) {
        if (!chunks[c]) continue;
        const Node& root = chunks[c]->nodes[0];
        items.push_back(
            {{root.lo[0] + root.hi[0], root.lo[1] + root.hi[1], root.lo[2] + root.hi[2]}, c});
    }
    top = split_tree(items, 1);
    top_ids.resize(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) top_ids[i] = items[i].id;
    fit_boxes(top, [&](const Node& leaf) {
        Box box;
        for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
            const Node& root = chunks[top_ids[i]]->nodes[0];
            box.grow(root.lo);
            box.grow(root.hi);
        }
        return box;
    });
}

namespace {

/// A body's Impl with `mesh`'s materials, pose and `options`; positions and indices empty.
std::unique_ptr<CollisionBody::Impl> mesh_without_corners(const CollisionMeshView& mesh,
                                                          const BuildOptions& options) {
    auto impl = std::make_unique<CollisionBody::Impl>();
    if (mesh.materials.empty()) {
        impl->materials.assign(mesh.triangle_count(), Material::kCortical);
    } else {
        impl->materials.assign(mesh.materials.begin(), mesh.materials.end());
    }
    impl->pose = mesh.world_from_body;
    impl->options = options;
    impl->options.chunk_triangles = std::max<std::uint32_t>(options.chunk_triangles, 1);
    impl->options.leaf_triangles = std::max<std::uint32_t>(options.leaf_triangles, 1);
    return impl;
}

std::unique_ptr<CollisionBody::Impl> copy_mesh(const CollisionMeshView& mesh,
                                               const BuildOptions& options) {
    auto impl = mesh_without_corners(mesh, options);
    impl->positions.assign(mesh.positions_m.begin(), mesh.positions_m.end());
    impl->indices.assign(mesh.indices.begin(), mesh.indices.end());
    return impl;
}

}  // namespace

CollisionBody::Built CollisionBody::build(const CollisionMeshView& mesh,
                                          const BuildOptions& options) {
    if (const MeshProblem problem = validate_mesh(mesh); problem.error != MeshError::kNone) {
        return Err{problem};
    }
    auto impl = copy_mesh(mesh, options);
    const auto n = static_cast<std::uint32_t>(mesh.triangle_count());
    impl->chunk_of.assign(n, 0);
    std::vector<Item> items(n);
    for (std::uint32_t t = 0; t < n; ++t) items[t] = impl->item(t);
    impl->add_chunks(std::move(items), impl->options.chunk_triangles);
    impl->build_top();
    return std::unique_ptr<const CollisionBody>(new CollisionBody(std::move(impl)));
}

CollisionBody::Built CollisionBody::update(const CollisionBody& previous,
                                           const CollisionMeshView& next, UpdateStats* stats) {
    // One pass per array, block by block: compared with the previous mesh, checked only where it
    // differs (the previous mesh passed validate_mesh), copied. A cut appends vertices and
    // triangles and rewrites a few triangles in place. Any refusal is validate_mesh's own answer
    // (the first offender), which reads the whole mesh again.
    const auto refused = [&] { return Err{validate_mesh(next)}; };
    if (validate_mesh_shape(next).error != MeshError::kNone) return refused();
    const Impl& old = *previous.impl_;
    auto impl = mesh_without_corners(next, old.options);
    if (!all_pass(std::span<const Material>(impl->materials),
                  [](Material m) { return material_ok(m); })) {
        return refused();
    }

    // Vertices whose position changed (new vertices are only reachable through changed indices).
    constexpr std::size_t kVertexBlock = 1024;
    const std::size_t old_vertices = old.positions.size() / 3;
    const std::size_t new_vertices = next.vertex_count();
    const std::size_t common_vertices = std::min(old_vertices, new_vertices);
    std::vector<std::uint8_t> moved(old_vertices, 1);  // vertices past the new count are gone
    std::fill(moved.begin(), moved.begin() + common_vertices, 0);
    bool any_moved = common_vertices < old_vertices, elements_ok = true;
    impl->positions.reserve(next.positions_m.size());
    for (std::size_t v0 = 0; v0 < new_vertices; v0 += kVertexBlock) {
        const std::size_t n = std::min(kVertexBlock, new_vertices - v0);
        const std::span<const float> block = next.positions_m.subspan(3 * v0, 3 * n);
        const std::size_t kept = v0 < common_vertices ? std::min(n, common_vertices - v0) : 0;
        if (kept < n || std::memcmp(&old.positions[3 * v0], block.data(), 12 * n) != 0) {
            elements_ok = elements_ok && all_pass(block, [](float c) { return position_ok(c); });
            for (std::size_t v = v0; v < v0 + kept; ++v) {
                moved[v] = std::memcmp(&old.positions[3 * v], &block[3 * (v - v0)], 12) != 0;
                any_moved = any_moved || moved[v];
            }
        }
        impl->positions.insert(impl->positions.end(), block.begin(), block.end());
    }
    if (!elements_ok) return refused();

    // Triangles changed in place (indices, material or a moved corner) mark their chunk dirty.
    // Indices equal to the previous mesh's are in range unless vertices were removed.
    constexpr std::size_t kTriangleBlock = 256;
    const std::size_t old_count = old.indices.size() / 3, new_count = next.triangle_count();
    const std::size_t common = std::min(old_count, new_count);
    const bool check_every_index = new_vertices < old_vertices;
    const auto in_range = [limit = std::min<std::size_t>(new_vertices, 0xFFFFFFFFu)](
                              std::uint32_t i) { return i < limit; };
    std::vector<std::uint8_t> dirty(old.chunks.size(), 0);
    std::vector<std::uint8_t> changed(common, 0);  // per triangle kept in place
    impl->indices.reserve(next.indices.size());
    for (std::size_t t0 = 0; t0 < new_count; t0 += kTriangleBlock) {
        const std::size_t n = std::min(kTriangleBlock, new_count - t0);
        const std::span<const std::uint32_t> block = next.indices.subspan(3 * t0, 3 * n);
        const std::size_t kept = t0 < common ? std::min(n, common - t0) : 0;
        const bool same_indices =
            kept == n && std::memcmp(&old.indices[3 * t0], block.data(), 12 * n) == 0;
        if (!same_indices || check_every_index) {
            elements_ok = elements_ok && all_pass(block, in_range);
        }
        impl->indices.insert(impl->indices.end(), block.begin(), block.end());
        if (kept == 0 || (same_indices && !any_moved &&
                          std::memcmp(&old.materials[t0], &impl->materials[t0], n) == 0)) {
            continue;
        }
        for (std::size_t t = t0; t < t0 + kept; ++t) {
            const std::uint32_t* a = &old.indices[3 * t];
            const std::uint32_t* b = &block[3 * (t - t0)];
            const bool same = a[0] == b[0] && a[1] == b[1] && a[2] == b[2] &&
                              old.materials[t] == impl->materials[t] &&
                              (!any_moved || (!moved[a[0]] && !moved[a[1]] && !moved[a[2]]));
            if (!same) dirty[old.chunk_of[t]] = 1, changed[t] = 1;
        }
    }
    if (!elements_ok) return refused();
    for (std::size_t t = common; t < old_count; ++t) dirty[old.chunk_of[t]] = 1;  // removed

    // Chunk slots stay where they were: unchanged ones shared, changed ones refitted, ones that
    // lost triangles rebuilt from the survivors (or emptied); new triangles get new slots. A
    // chunk is a set of triangle indices: when a body loses faces, the indices after them shift
    // and a slot's triangles are no longer neighbours. A changed chunk whose box grew past
    // kRegroupGrowth is emptied and its triangles are grouped afresh with the new ones.
    constexpr double kRegroupGrowth = 1.25;  // box half-perimeter, new / old
    UpdateStats s;
    impl->chunk_of.resize(new_count);
    std::copy(old.chunk_of.begin(), old.chunk_of.begin() + common, impl->chunk_of.begin());
    impl->chunks = old.chunks;
    std::vector<Item> regroup;
    for (std::size_t c = 0; c < old.chunks.size(); ++c) {
        if (!dirty[c] || !old.chunks[c]) continue;
        const Chunk& chunk = *old.chunks[c];
        // Refitted when it keeps every triangle (the common case: a cut shrinks the triangles it
        // splits in place); its triangles are listed only when it must be rebuilt or regrouped.
        const bool keeps_all =
            !chunk.has_pieces() && std::all_of(chunk.tris.begin(), chunk.tris.end(),
                                               [&](const Tri& t) { return t.id < new_count; });
        std::vector<Item> survivors;
        if (keeps_all) {
            impl->chunks[c] = impl->refit_chunk(chunk, changed.data());
            ++s.chunks_refitted;
            s.triangles_touched += chunk.tris.size();
        } else {
            survivors = impl->triangles_of(chunk, static_cast<std::uint32_t>(new_count));
            s.triangles_touched += survivors.size();
            impl->chunks[c] = survivors.empty() ? nullptr : impl->build_chunk(survivors);
            ++s.chunks_rebuilt;
        }
        if (impl->chunks[c] && half_perimeter(impl->chunks[c]->nodes[0]) >
                                   kRegroupGrowth * half_perimeter(chunk.nodes[0])) {
            if (keeps_all) {
                survivors = impl->triangles_of(chunk, static_cast<std::uint32_t>(new_count));
            }
            impl->chunks[c] = nullptr;
            ++s.chunks_regrouped;
            regroup.insert(regroup.end(), survivors.begin(), survivors.end());
        }
    }
    std::vector<Item> added = std::move(regroup);
    added.reserve(added.size() + new_count - common);
    for (std::size_t t = common; t < new_count; ++t) {
        added.push_back(impl->item(static_cast<std::uint32_t>(t)));
    }
    const std::size_t before = impl->chunks.size();
    s.triangles_touched += new_count - common;
    impl->add_chunks(std::move(added), impl->options.chunk_triangles);
    s.chunks_rebuilt += static_cast<std::uint32_t>(impl->chunks.size() - before);
    impl->build_top();
    for (const auto& c : impl->chunks) s.chunks_total += c ? 1 : 0;
    if (stats) *stats = s;
    return std::unique_ptr<const CollisionBody>(new CollisionBody(std::move(impl)));
}

CollisionBody::Built CollisionBody::refit(const CollisionBody& previous,
                                          const CollisionMeshView& next) {
    if (const MeshProblem problem = validate_mesh(next); problem.error != MeshError::kNone) {
        return Err{problem};
    }
    const Impl& old = *previous.impl_;
    if (next.indices.size() != old.indices.size()) {
        return Err{MeshProblem{MeshError::kIndexOutOfRange, 0}};
    }
    for (std::size_t i = 0; i < old.indices.size(); ++i) {
        if (old.indices[i] != next.indices[i])
            return Err{MeshProblem{MeshError::kIndexOutOfRange, i}};
    }
    auto impl = copy_mesh(next, old.options);
    impl->chunk_of = old.chunk_of;
    impl->chunks.reserve(old.chunks.size());
    for (const auto& c : old.chunks) impl->chunks.push_back(c ? impl->refit_chunk(*c) : nullptr);
    impl->build_top();
    return std::unique_ptr<const CollisionBody>(new CollisionBody(std::move(impl)));
}

CollisionBody::CollisionBody(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
CollisionBody::~CollisionBody() = default;

namespace {

Vec3 load(const float* p) noexcept { return {p[0], p[1], p[2]}; }

Vec3 tri_normal(const Tri& t) noexcept {
    const Vec3 a = load(t.v), b = load(t.v + 3), c = load(t.v + 6);
    return normalized(cross(b - a, c - a));
}

/// Visits the leaves of `nodes` whose boxes pass `enter(node)`, nearest first by `key(node)`
/// (smaller is nearer; `enter` sees the current bound), calling `leaf(node)`.
/// Squared distance from `p` to the centre of `n`'s box: orders children whose boxes both
/// contain the query point (box distance 0), common for points inside a body.
double centre_distance2(const Vec3& p, const Node& n) noexcept {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double e = p[i] - 0.5 * (double(n.lo[i]) + double(n.hi[i]));
        d2 += e * e;
    }
    return d2;
}

template <class Key, class Enter, class Leaf>
void traverse(const std::vector<Node>& nodes, const Vec3& origin, const Key& key,
              const Enter& enter, const Leaf& leaf) noexcept {
    std::uint32_t stack[kStackSize];
    int top = 0;
    if (nodes.empty() || !enter(nodes[0], key(nodes[0]))) return;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes[stack[--top]];
        if (!enter(node, key(node))) continue;  // the bound may have shrunk since the push
        if (node.count > 0) {
            leaf(node);
            continue;
        }
        const std::uint32_t a = node.first, b = node.first + 1;
        const double ka = key(nodes[a]), kb = key(nodes[b]);
        const bool a_first = ka < kb || (ka == kb && centre_distance2(origin, nodes[a]) <=
                                                         centre_distance2(origin, nodes[b]));
        const std::uint32_t near = a_first ? a : b, far = a_first ? b : a;
        const double k_near = a_first ? ka : kb, k_far = a_first ? kb : ka;
        if (top + 2 > kStackSize) return;  // cannot happen for trees this library builds
        if (enter(nodes[far], k_far)) stack[top++] = far;
        if (enter(nodes[near], k_near)) stack[top++] = near;
    }
}

/// Visits every leaf of `nodes` whose box and ancestors' boxes pass `enter(node)`, in no order.
template <class Enter, class Leaf>
void visit_leaves(const std::vector<Node>& nodes, const Enter& enter, const Leaf& leaf) noexcept {
    std::uint32_t stack[kStackSize];
    int top = 0;
    if (nodes.empty() || !enter(nodes[0])) return;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes[stack[--top]];
        if (node.count > 0) {
            leaf(node);
            continue;
        }
        if (top + 2 > kStackSize) return;  // cannot happen for trees this library builds
        for (std::uint32_t c = node.first; c < node.first + 2; ++c) {
            if (enter(nodes[c])) stack[top++] = c;
        }
    }
}

/// Visits the chunks whose boxes pass `enter`, nearest first by `key`.
template <class Key, class Enter, class Visit>
void for_each_chunk(const CollisionBody::Impl& impl, const Vec3& origin, const Key& key,
                    const Enter& enter, const Visit& visit) noexcept {
    traverse(impl.top, origin, key, enter, [&](const Node& top_leaf) {
        for (std::uint32_t i = top_leaf.first; i < top_leaf.first + top_leaf.count; ++i) {
            const Chunk& chunk = *impl.chunks[impl.top_ids[i]];
            if (enter(chunk.nodes[0], key(chunk.nodes[0]))) visit(chunk);
        }
    });
}

}  // namespace

SurfaceHit CollisionBody::closest_point(const Vec3& p, double max_distance,
                                        MaterialMask materials) const noexcept {
    SurfaceHit hit;
    double best2 = max_distance * max_distance;
    const Tri* best = nullptr;
    const bool filter = (materials & kAllMaterials) != kAllMaterials;
    const auto key = [&](const Node& n) { return box_distance2(p, n.lo, n.hi); };
    const auto enter = [&](const Node&, double d2) { return d2 <= best2; };
    for_each_chunk(*impl_, p, key, enter, [&](const Chunk& chunk) {
        traverse(chunk.nodes, p, key, enter, [&](const Node& leaf) {
            for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                const Tri& t = chunk.tris[i];
                if (filter && !((materials >> static_cast<int>(impl_->materials[t.id])) & 1u))
                    continue;
                const Vec3 q =
                    closest_point_on_triangle(p, load(t.v), load(t.v + 3), load(t.v + 6));
                const double d2 = norm2(q - p);
                if (d2 <= best2) best2 = d2, best = &t, hit.point = q;
            }
        });
    });
    if (!best) return hit;
    hit.found = true;
    hit.triangle = best->id;
    hit.normal = tri_normal(*best);
    hit.distance = std::sqrt(best2);
    hit.material = impl_->materials[best->id];
    return hit;
}

SegmentHit CollisionBody::first_hit(const Vec3& from, const Vec3& to,
                                    HitSides sides) const noexcept {
    SegmentHit hit;
    const Vec3 d = to - from;
    const Vec3 inv{1.0 / d.x, 1.0 / d.y, 1.0 / d.z};
    double best_t = 1;
    const Tri* best = nullptr;
    const bool front = sides == HitSides::kFront;
    const auto key = [&](const Node& n) { return box_distance2(from, n.lo, n.hi); };
    const auto enter = [&](const Node& n, double) {
        return segment_hits_box(from, inv, best_t, n.lo, n.hi);
    };
    for_each_chunk(*impl_, from, key, enter, [&](const Chunk& chunk) {
        traverse(chunk.nodes, from, key, enter, [&](const Node& leaf) {
            for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                const Tri& t = chunk.tris[i];
                const double s = segment_triangle_t(from, d, best_t, load(t.v), load(t.v + 3),
                                                    load(t.v + 6), front);
                if (s >= 0 && (s < best_t || !best)) best_t = s, best = &t;
            }
        });
    });
    if (!best) return hit;
    hit.found = true;
    hit.triangle = best->id;
    hit.t = best_t;
    hit.point = from + d * best_t;
    hit.normal = tri_normal(*best);
    hit.material = impl_->materials[best->id];
    return hit;
}

namespace {

/// Whether one of the first `found` entries of `out` (those it holds) matches `same`.
template <class T, class Same>
bool listed(std::span<T> out, std::size_t found, const Same& same) noexcept {
    const std::size_t n = std::min(found, out.size());
    for (std::size_t i = 0; i < n; ++i) {
        if (same(out[i])) return true;
    }
    return false;
}

}  // namespace

std::size_t CollisionBody::crossings(const Vec3& from, const Vec3& to,
                                     std::span<SegmentCrossing> out) const noexcept {
    std::size_t found = 0;
    const Vec3 d = to - from;
    const Vec3 inv{1.0 / d.x, 1.0 / d.y, 1.0 / d.z};
    const auto enter = [&](const Node& n) { return segment_hits_box(from, inv, 1.0, n.lo, n.hi); };
    visit_leaves(impl_->top, enter, [&](const Node& top_leaf) {
        for (std::uint32_t c = top_leaf.first; c < top_leaf.first + top_leaf.count; ++c) {
            const Chunk& chunk = *impl_->chunks[impl_->top_ids[c]];
            visit_leaves(chunk.nodes, enter, [&](const Node& leaf) {
                for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                    const Tri& t = chunk.tris[i];
                    const TriangleCrossing x =
                        segment_crossing(from, d, load(t.v), load(t.v + 3), load(t.v + 6));
                    if (x.sign == 0) continue;
                    // A triangle in pieces is seen from each piece the segment passes.
                    if (chunk.has_pieces() && listed(out, found, [&](const SegmentCrossing& o) {
                            return o.triangle == t.id;
                        })) {
                        continue;
                    }
                    if (found < out.size()) out[found] = {x.t, 0, t.id, x.sign};
                    ++found;
                }
            });
        }
    });
    return found;
}

std::size_t CollisionBody::triangles_near(const Vec3& center, double radius,
                                          std::span<std::uint32_t> out) const noexcept {
    std::size_t found = 0;
    const double r2 = radius * radius;
    const auto key = [&](const Node& n) { return box_distance2(center, n.lo, n.hi); };
    const auto enter = [&](const Node&, double d2) { return d2 <= r2; };
    for_each_chunk(*impl_, center, key, enter, [&](const Chunk& chunk) {
        traverse(chunk.nodes, center, key, enter, [&](const Node& leaf) {
            for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                const Tri& t = chunk.tris[i];
                const Vec3 q =
                    closest_point_on_triangle(center, load(t.v), load(t.v + 3), load(t.v + 6));
                if (norm2(q - center) > r2) continue;
                if (chunk.has_pieces() &&
                    listed(out, found, [&](std::uint32_t o) { return o == t.id; })) {
                    continue;
                }
                if (found < out.size()) out[found] = t.id;
                ++found;
            }
        });
    });
    return found;
}

std::size_t CollisionBody::triangle_count() const noexcept { return impl_->indices.size() / 3; }
std::size_t CollisionBody::vertex_count() const noexcept { return impl_->positions.size() / 3; }
Material CollisionBody::material(std::uint32_t triangle) const noexcept {
    return triangle < impl_->materials.size() ? impl_->materials[triangle] : Material::kCortical;
}
TriangleCorners CollisionBody::corners(std::uint32_t triangle) const noexcept {
    if (triangle >= triangle_count()) return {};
    return {load(impl_->corner(triangle, 0)), load(impl_->corner(triangle, 1)),
            load(impl_->corner(triangle, 2))};
}
const RigidTransform& CollisionBody::world_from_body() const noexcept { return impl_->pose; }
void CollisionBody::bounds(Vec3& lo, Vec3& hi) const noexcept {
    const Node& root = impl_->top[0];
    lo = load(root.lo);
    hi = load(root.hi);
}
std::uint32_t CollisionBody::chunk_count() const noexcept {
    return static_cast<std::uint32_t>(impl_->top_ids.size());
}
std::size_t CollisionBody::memory_bytes() const noexcept {
    std::size_t bytes =
        impl_->positions.capacity() * sizeof(float) +
        impl_->indices.capacity() * sizeof(std::uint32_t) + impl_->materials.capacity() +
        impl_->chunk_of.capacity() * sizeof(std::uint32_t) + impl_->top.capacity() * sizeof(Node);
    for (const auto& c : impl_->chunks) {
        if (c) {
            bytes += c->nodes.capacity() * sizeof(Node) + c->tris.capacity() * sizeof(Tri) +
                     c->piece_box.capacity() * sizeof(Box);
        }
    }
    return bytes;
}

}  // namespace kerf::physics
