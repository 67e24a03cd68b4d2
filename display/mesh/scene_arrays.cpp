#include "display/mesh/scene_arrays.hpp"

#include "display/mesh/foot_generator.hpp"
#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/mesh_io.hpp"

namespace kerf::mesh {
namespace {

std::array<float, 16> column_major(const config::RigidTransform& t) {
    const double w = t.rotation_wxyz[0], x = t.rotation_wxyz[1], y = t.rotation_wxyz[2],
                 z = t.rotation_wxyz[3];
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                            {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                            {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    std::array<float, 16> m{};
    for (int c = 0; c < 3; ++c) {
        for (int row = 0; row < 3; ++row) m[4 * c + row] = float(r[row][c]);
    }
    for (int i = 0; i < 3; ++i) m[12 + i] = float(t.translation_m[i]);
    m[15] = 1.f;
    return m;
}

BodyArrays to_arrays(const IndexedMesh& in, double scale, const config::SceneBody& body) {
    BodyArrays out;
    out.name = body.name;
    out.positions_m.reserve(3 * in.positions_m.size());
    for (const Point& p : in.positions_m) {
        for (int k = 0; k < 3; ++k) out.positions_m.push_back(float(p[k] * scale));
    }
    const auto fallback = std::uint8_t(body.material == config::BodyMaterial::kCancellous ? 1 : 0);
    out.indices.reserve(3 * in.triangles.size());
    out.materials.reserve(in.triangles.size());
    for (const Triangle& t : in.triangles) {
        out.indices.insert(out.indices.end(), t.begin(), t.end());
        out.materials.push_back(in.materials.empty() ? fallback : std::uint8_t(in.materials[t[0]]));
    }
    out.world_from_body = column_major(body.transform);
    return out;
}

}  // namespace

Result<std::vector<BodyArrays>, std::string> load_scene_arrays(const config::Scene& scene,
                                                               const config::PathVars& vars) {
    std::vector<BodyArrays> bodies;
    for (const config::SceneBody& body : scene.bodies) {
        if (body.mesh.kind == config::MeshSourceKind::kBuiltinFoot) {
            auto foot = generate_foot({body.mesh.target_triangles, body.mesh.seed});
            if (!foot) return Err{"scene body '" + body.name + "': " + foot.error()};
            bodies.push_back(to_arrays(to_indexed(foot->mesh), 1.0, body));
            continue;
        }
        auto path = config::resolve_mesh_path(body, vars);
        if (!path) return Err{path.error().message()};
        auto loaded = load_mesh_file(*path, LengthUnit::kMetre);
        if (!loaded) return Err{"scene body '" + body.name + "': " + loaded.error().message()};
        bodies.push_back(to_arrays(loaded->indexed, metres_per_unit(body.mesh.units), body));
    }
    return bodies;
}

}  // namespace kerf::mesh
