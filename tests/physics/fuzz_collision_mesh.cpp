// libFuzzer target for the collision mesh input (what kerf-rt takes from the display's mailbox):
// the bytes become vertex count, positions, indices and materials; every input is validated, and
// each accepted one is built and queried (closest point, segment, neighbourhood, a contact step)
// and updated from a second mesh cut from the same bytes. Nothing may crash, and a refused mesh
// must name its error.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "rt_core/physics/proxy_contact.hpp"

namespace {

using namespace kerf::physics;

struct Parsed {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::vector<Material> materials;
};

Parsed parse(const std::uint8_t* data, std::size_t size) {
    Parsed p;
    if (size < 2) return p;
    const std::size_t vertices = data[0] % 32, flags = data[1];
    std::size_t at = 2;
    for (std::size_t i = 0; i < 3 * vertices && at + 4 <= size; ++i, at += 4) {
        float f;
        std::memcpy(&f, data + at, 4);
        p.positions.push_back(f);
    }
    while (at + 1 <= size) {
        // Indices mostly in range (interesting meshes), sometimes anything.
        const std::uint32_t raw = data[at++];
        p.indices.push_back((flags & 1) ? raw : raw % (vertices ? vertices : 1));
        if ((flags & 2) && p.indices.size() % 3 == 0) p.materials.push_back(Material(raw % 4));
    }
    return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const Parsed a = parse(data, size);
    const CollisionMeshView view{a.positions, a.indices, a.materials, {}};
    auto built = CollisionBody::build(view, {.chunk_triangles = 4, .leaf_triangles = 2});
    if (!built) {
        if (built.error().error == MeshError::kNone || to_string(built.error().error).empty()) {
            __builtin_trap();
        }
        return 0;
    }
    const CollisionBody& body = **built;
    CollisionWorld world;
    world.set_body(0, &body);
    std::uint32_t near[8];
    for (float s : {0.0f, 0.5f, -3.0f}) {
        const Vec3 p{s, s * 0.5, 1.0};
        (void)world.closest_point(p, 100);
        (void)world.first_hit(p, -p, HitSides::kBoth);
        (void)body.triangles_near(p, 5, near);
    }
    ProxyContact contact;
    contact.reset({20, 20, 20});
    (void)contact.step(world, {0, 0, 0}, {1, 0, 0}, 1e-3);
    // An "edit": the same bytes shifted by one give a second mesh to update to.
    if (size > 1) {
        const Parsed b = parse(data + 1, size - 1);
        UpdateStats stats;
        auto updated =
            CollisionBody::update(body, {b.positions, b.indices, b.materials, {}}, &stats);
        if (updated) (void)(*updated)->closest_point({0, 0, 0}, 100);
    }
    return 0;
}
