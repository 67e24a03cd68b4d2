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

/// Builds a median-split tree over `items` (reordered so that every leaf is a contiguous range).
/// `box_of(item)` and `centre_of(item, axis)` describe the items.
template <class BoxOf, class CentreOf>
std::vector<Node> build_tree(std::vector<std::uint32_t>& items, std::uint32_t max_leaf,
                             const BoxOf& box_of, const CentreOf& centre_of) {
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
        Box box, centres;
        for (std::uint32_t i = job.begin; i < job.end; ++i) {
            box.grow(box_of(items[i]));
            const float c[3] = {centre_of(items[i], 0), centre_of(items[i], 1),
                                centre_of(items[i], 2)};
            centres.grow(c);
        }
        store_box(nodes[job.node], box);
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
                         [&](std::uint32_t a, std::uint32_t b) {
                             return centre_of(a, axis) < centre_of(b, axis);
                         });
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

/// One chunk: its own tree over its triangles' corners.
struct Chunk {
    std::vector<Node> nodes;
    std::vector<Tri> tris;
};

constexpr int kStackSize = 128;  ///< > 2 x (top depth + chunk depth) for 2^26 triangles

}  // namespace

struct CollisionBody::Impl {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::vector<Material> materials;
    std::vector<std::uint32_t> chunk_of;  ///< per triangle
    std::vector<std::shared_ptr<const Chunk>> chunks;
    std::vector<Node> top;               ///< tree over the chunks; leaves index top_ids
    std::vector<std::uint32_t> top_ids;  ///< chunk indices in top-leaf order
    RigidTransform pose;
    BuildOptions options;

    const float* corner(std::uint32_t tri, int k) const noexcept {
        return &positions[3 * std::size_t{indices[3 * std::size_t{tri} + k]}];
    }
    Box tri_box(std::uint32_t tri) const noexcept {
        Box b;
        for (int k = 0; k < 3; ++k) b.grow(corner(tri, k));
        return b;
    }
    float tri_centre(std::uint32_t tri, int axis) const noexcept {
        return corner(tri, 0)[axis] + corner(tri, 1)[axis] + corner(tri, 2)[axis];
    }
    std::shared_ptr<const Chunk> build_chunk(std::vector<std::uint32_t> ids) const;
    void add_chunks(std::vector<std::uint32_t> ids);
    void build_top();
};

std::shared_ptr<const Chunk> CollisionBody::Impl::build_chunk(
    std::vector<std::uint32_t> ids) const {
    auto chunk = std::make_shared<Chunk>();
    chunk->nodes = build_tree(
        ids, options.leaf_triangles, [&](std::uint32_t t) { return tri_box(t); },
        [&](std::uint32_t t, int axis) { return tri_centre(t, axis); });
    chunk->tris.resize(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        Tri& tri = chunk->tris[i];
        for (int k = 0; k < 3; ++k)
            std::memcpy(&tri.v[3 * k], corner(ids[i], k), 3 * sizeof(float));
        tri.id = ids[i];
    }
    return chunk;
}

/// Splits `ids` spatially into groups of at most chunk_triangles and builds a chunk of each.
void CollisionBody::Impl::add_chunks(std::vector<std::uint32_t> ids) {
    if (ids.empty()) return;
    const std::vector<Node> groups = build_tree(
        ids, options.chunk_triangles, [&](std::uint32_t t) { return tri_box(t); },
        [&](std::uint32_t t, int axis) { return tri_centre(t, axis); });
    for (const Node& g : groups) {
        if (g.count == 0) continue;
        const auto index = static_cast<std::uint32_t>(chunks.size());
        std::vector<std::uint32_t> members(ids.begin() + g.first, ids.begin() + g.first + g.count);
        for (std::uint32_t t : members) chunk_of[t] = index;
        chunks.push_back(build_chunk(std::move(members)));
    }
}

void CollisionBody::Impl::build_top() {
    std::vector<std::uint32_t> ids(chunks.size());
    std::iota(ids.begin(), ids.end(), 0u);
    const auto box_of = [&](std::uint32_t c) {
        Box b;
        const Node& root = chunks[c]->nodes[0];
        b.grow(root.lo);
        b.grow(root.hi);
        return b;
    };
    const auto centre_of = [&](std::uint32_t c, int axis) {
        const Node& root = chunks[c]->nodes[0];
        return root.lo[axis] + root.hi[axis];
    };
    top = build_tree(ids, 1, box_of, centre_of);
    top_ids = std::move(ids);
}

namespace {

std::unique_ptr<CollisionBody::Impl> copy_mesh(const CollisionMeshView& mesh,
                                               const BuildOptions& options) {
    auto impl = std::make_unique<CollisionBody::Impl>();
    impl->positions.assign(mesh.positions_m.begin(), mesh.positions_m.end());
    impl->indices.assign(mesh.indices.begin(), mesh.indices.end());
    if (mesh.materials.empty()) {
        impl->materials.assign(mesh.triangle_count(), Material::kCortical);
    } else {
        impl->materials.assign(mesh.materials.begin(), mesh.materials.end());
    }
    impl->chunk_of.assign(mesh.triangle_count(), 0);
    impl->pose = mesh.world_from_body;
    impl->options = options;
    impl->options.chunk_triangles = std::max<std::uint32_t>(options.chunk_triangles, 1);
    impl->options.leaf_triangles = std::max<std::uint32_t>(options.leaf_triangles, 1);
    return impl;
}

}  // namespace

CollisionBody::Built CollisionBody::build(const CollisionMeshView& mesh,
                                          const BuildOptions& options) {
    if (const MeshProblem problem = validate_mesh(mesh); problem.error != MeshError::kNone) {
        return Err{problem};
    }
    auto impl = copy_mesh(mesh, options);
    std::vector<std::uint32_t> ids(mesh.triangle_count());
    std::iota(ids.begin(), ids.end(), 0u);
    impl->add_chunks(std::move(ids));
    impl->build_top();
    return std::unique_ptr<const CollisionBody>(new CollisionBody(std::move(impl)));
}

CollisionBody::Built CollisionBody::update(const CollisionBody& previous,
                                           const CollisionMeshView& next, UpdateStats* stats) {
    if (const MeshProblem problem = validate_mesh(next); problem.error != MeshError::kNone) {
        return Err{problem};
    }
    const Impl& old = *previous.impl_;
    auto impl = copy_mesh(next, old.options);
    const std::size_t old_count = old.indices.size() / 3, new_count = next.triangle_count();
    std::vector<char> dirty(old.chunks.size(), 0);
    for (std::size_t t = 0; t < old_count; ++t) {
        bool same = t < new_count && impl->materials[t] == old.materials[t];
        for (int k = 0; same && k < 3; ++k) {
            const auto tri = static_cast<std::uint32_t>(t);
            same = old.indices[3 * t + k] == impl->indices[3 * t + k] &&
                   std::memcmp(old.corner(tri, k), impl->corner(tri, k), 3 * sizeof(float)) == 0;
        }
        if (!same) dirty[old.chunk_of[t]] = 1;
    }
    UpdateStats s;
    for (std::size_t c = 0; c < old.chunks.size(); ++c) {
        std::vector<std::uint32_t> members;
        members.reserve(old.chunks[c]->tris.size());
        for (const Tri& tri : old.chunks[c]->tris) {
            if (tri.id < new_count) members.push_back(tri.id);
        }
        if (members.empty()) continue;
        const auto index = static_cast<std::uint32_t>(impl->chunks.size());
        for (std::uint32_t t : members) impl->chunk_of[t] = index;
        if (dirty[c]) {
            s.triangles_rebuilt += members.size();
            ++s.chunks_rebuilt;
            impl->chunks.push_back(impl->build_chunk(std::move(members)));
        } else {
            impl->chunks.push_back(old.chunks[c]);  // shared, unchanged
        }
    }
    std::vector<std::uint32_t> added;
    for (std::size_t t = old_count; t < new_count; ++t)
        added.push_back(static_cast<std::uint32_t>(t));
    const std::size_t before = impl->chunks.size();
    s.triangles_rebuilt += added.size();
    impl->add_chunks(std::move(added));
    s.chunks_rebuilt += static_cast<std::uint32_t>(impl->chunks.size() - before);
    impl->build_top();
    s.chunks_total = static_cast<std::uint32_t>(impl->chunks.size());
    if (stats) *stats = s;
    return std::unique_ptr<const CollisionBody>(new CollisionBody(std::move(impl)));
}

CollisionBody::Built CollisionBody::refit(const CollisionBody& previous,
                                          const CollisionMeshView& next) {
    if (const MeshProblem problem = validate_mesh(next); problem.error != MeshError::kNone) {
        return Err{problem};
    }
    const Impl& old = *previous.impl_;
    if (next.indices.size() != old.indices.size())
        return Err{MeshProblem{MeshError::kIndexOutOfRange, 0}};
    for (std::size_t i = 0; i < old.indices.size(); ++i) {
        if (old.indices[i] != next.indices[i])
            return Err{MeshProblem{MeshError::kIndexOutOfRange, i}};
    }
    auto impl = copy_mesh(next, old.options);
    impl->chunk_of = old.chunk_of;
    for (const auto& old_chunk : old.chunks) {
        auto chunk = std::make_shared<Chunk>(*old_chunk);
        for (Tri& tri : chunk->tris) {
            for (int k = 0; k < 3; ++k)
                std::memcpy(&tri.v[3 * k], impl->corner(tri.id, k), 3 * sizeof(float));
        }
        // Children follow their parent in the array, so a backward pass refits bottom-up.
        for (std::size_t n = chunk->nodes.size(); n-- > 0;) {
            Node& node = chunk->nodes[n];
            Box box;
            if (node.count > 0) {
                for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                    for (int k = 0; k < 3; ++k) box.grow(&chunk->tris[i].v[3 * k]);
                }
            } else {
                for (std::uint32_t c = node.first; c < node.first + 2; ++c) {
                    box.grow(chunk->nodes[c].lo);
                    box.grow(chunk->nodes[c].hi);
                }
            }
            store_box(node, box);
        }
        impl->chunks.push_back(std::move(chunk));
    }
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
template <class Key, class Enter, class Leaf>
void traverse(const std::vector<Node>& nodes, const Key& key, const Enter& enter,
              const Leaf& leaf) noexcept {
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
        const bool a_first = ka <= kb;
        const std::uint32_t near = a_first ? a : b, far = a_first ? b : a;
        const double k_near = a_first ? ka : kb, k_far = a_first ? kb : ka;
        if (top + 2 > kStackSize) return;  // cannot happen for trees this library builds
        if (enter(nodes[far], k_far)) stack[top++] = far;
        if (enter(nodes[near], k_near)) stack[top++] = near;
    }
}

/// Visits the chunks whose boxes pass `enter`, nearest first by `key`.
template <class Key, class Enter, class Visit>
void for_each_chunk(const CollisionBody::Impl& impl, const Key& key, const Enter& enter,
                    const Visit& visit) noexcept {
    traverse(impl.top, key, enter, [&](const Node& top_leaf) {
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
    for_each_chunk(*impl_, key, enter, [&](const Chunk& chunk) {
        traverse(chunk.nodes, key, enter, [&](const Node& leaf) {
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
    for_each_chunk(*impl_, key, enter, [&](const Chunk& chunk) {
        traverse(chunk.nodes, key, enter, [&](const Node& leaf) {
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

std::size_t CollisionBody::triangles_near(const Vec3& center, double radius,
                                          std::span<std::uint32_t> out) const noexcept {
    std::size_t found = 0;
    const double r2 = radius * radius;
    const auto key = [&](const Node& n) { return box_distance2(center, n.lo, n.hi); };
    const auto enter = [&](const Node&, double d2) { return d2 <= r2; };
    for_each_chunk(*impl_, key, enter, [&](const Chunk& chunk) {
        traverse(chunk.nodes, key, enter, [&](const Node& leaf) {
            for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                const Tri& t = chunk.tris[i];
                const Vec3 q =
                    closest_point_on_triangle(center, load(t.v), load(t.v + 3), load(t.v + 6));
                if (norm2(q - center) > r2) continue;
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
    return static_cast<std::uint32_t>(impl_->chunks.size());
}
std::size_t CollisionBody::memory_bytes() const noexcept {
    std::size_t bytes =
        impl_->positions.capacity() * sizeof(float) +
        impl_->indices.capacity() * sizeof(std::uint32_t) + impl_->materials.capacity() +
        impl_->chunk_of.capacity() * sizeof(std::uint32_t) + impl_->top.capacity() * sizeof(Node);
    for (const auto& c : impl_->chunks) {
        bytes += c->nodes.capacity() * sizeof(Node) + c->tris.capacity() * sizeof(Tri);
    }
    return bytes;
}

}  // namespace kerf::physics
