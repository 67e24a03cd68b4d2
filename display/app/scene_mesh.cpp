#include "display/app/scene_mesh.hpp"

#include <vector>

#include "display/cut/session_events.hpp"
#include "display/mesh/foot_generator.hpp"
#include "display/mesh/mesh_io.hpp"

namespace kerf::display {
namespace {

/// Appends `part`, placed by `t`, to `scene` (every vertex attribute copied).
void append_placed(mesh::TriMesh& scene, const mesh::TriMesh& part,
                   const config::RigidTransform& t) {
    const cut::RigidPose place{
        cut::Vec3(t.translation_m[0], t.translation_m[1], t.translation_m[2]), t.rotation_wxyz};
    const cut::RigidPose turn{cut::Vec3(0, 0, 0), t.rotation_wxyz};
    const int offset = static_cast<int>(scene.n_vertices());
    for (const auto v : part.vertices()) {
        const auto w = scene.add_vertex(place.to_world(part.point(v)));
        scene.set_normal(w, turn.to_world(part.normal(v)));
        scene.set_texcoord2D(w, part.texcoord2D(v));
        scene.set_color(w, part.color(v));
        scene.data(w).set_material(part.data(v).material());
    }
    std::vector<mesh::VertexHandle> corners;
    for (const auto f : part.faces()) {
        corners.clear();
        for (const auto v : part.fv_range(f)) corners.emplace_back(v.idx() + offset);
        scene.add_face(corners);
    }
}

}  // namespace

Result<mesh::TriMesh, std::string> build_scene_mesh(const config::Config& config) {
    mesh::TriMesh scene = mesh::make_mesh();
    const config::PathVars vars = config::path_vars(config);
    for (const config::SceneBody& body : config.scene.bodies) {
        const std::string where = "scene " + config.scene.name + ", body " + body.name + ": ";
        if (body.mesh.kind == config::MeshSourceKind::kBuiltinFoot) {
            auto foot = mesh::generate_foot(
                {static_cast<std::size_t>(body.mesh.target_triangles), body.mesh.seed});
            if (!foot) return Err{where + foot.error()};
            append_placed(scene, foot->mesh, body.transform);
            continue;
        }
        auto path = config::resolve_mesh_path(body, vars);
        if (!path) return Err{where + path.error().message()};
        auto loaded = mesh::load_mesh(*path, body.mesh.units);
        if (!loaded) return Err{where + loaded.error().message()};
        append_placed(scene, *loaded, body.transform);
    }
    scene.update_face_normals();
    return scene;
}

}  // namespace kerf::display
