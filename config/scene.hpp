// kerf::config::Scene — the bones on the table (config/scenes/*.toml).
//
// A scene is a list of bodies; each body's mesh comes from a file (any format the mesh library
// reads, with the file's length unit) or from the built-in forefoot generator, and is placed by a
// rigid transform. Mesh paths are kept as written, `${shared}` / `${config}` and all, and expanded
// by `resolve_mesh_path()` with the directories the caller knows.
//
// Rotation in the TOML is written in exactly one of two forms (the struct always holds the
// normalised quaternion):
//   rotation_axis = [0.0, 0.0, 1.0] + rotation_angle_deg = 90.0   (right-handed, non-zero axis)
//   rotation_quaternion_wxyz = [1.0, 0.0, 0.0, 0.0]                (unit length within 1e-3)
// and the body is placed as x_world = R * (x_file * metres_per_unit) + translation_m.
// The same two forms rotate the device's frame in [device_mapping] (see DeviceMapping).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/length_unit.hpp"
#include "config/base/result.hpp"
#include "config/config_error.hpp"
#include "config/expand_path.hpp"

namespace kerf::config {

/// What a body is made of (the cutting resistance the force profile gives it).
enum class BodyMaterial : std::uint8_t { kCortical, kCancellous };
std::string_view to_string(BodyMaterial material) noexcept;

/// Where a body's triangles come from.
enum class MeshSourceKind : std::uint8_t { kFile, kBuiltinFoot };
std::string_view to_string(MeshSourceKind kind) noexcept;

/// A body's mesh source.
struct MeshSource {
    MeshSourceKind kind = MeshSourceKind::kBuiltinFoot;
    std::string path;                       ///< kFile: as written, may hold ${shared}/${config}
    LengthUnit units = LengthUnit::kMetre;  ///< kFile: the file's length unit
    std::uint64_t target_triangles = 0;     ///< kBuiltinFoot: approximate triangle count
    std::uint64_t seed = 0;                 ///< kBuiltinFoot: generator seed (deterministic)
};

/// Rigid placement of a body in the world frame.
struct RigidTransform {
    std::array<double, 3> translation_m{};
    std::array<double, 4> rotation_wxyz{1.0, 0.0, 0.0, 0.0};  ///< unit quaternion
};

/// One bone.
struct SceneBody {
    std::string name;
    MeshSource mesh;
    RigidTransform transform;
    BodyMaterial material = BodyMaterial::kCortical;
};

/// How the device's workspace maps into the scene ([device_mapping], optional):
///   x_world = origin_m + scale * R(rotation) * x_device      (metres; forces go back by R^T)
struct DeviceMapping {
    bool origin_given = false;  ///< false: origin_m is 20 mm above the scene's bounds, centred
    std::array<double, 3> origin_m{};  ///< world point the device's origin maps to, m
    double scale = 1.0;                ///< world metres per device metre (0.1 .. 10)
    std::array<double, 4> rotation_wxyz{1.0, 0.0, 0.0, 0.0};  ///< world from device, unit
};

/// The cut the surgeon is to make ([planned_cut], optional), world frame: the display draws it
/// as a guide; kerf-rt orients the blade by it when the device senses no orientation.
struct PlannedCut {
    std::array<double, 3> point_m{};        ///< a point on the plane, m
    std::array<double, 3> normal{0, 0, 1};  ///< unit plane normal
    std::array<double, 3> edge{1, 0, 0};    ///< unit blade edge direction, in the plane
    double half_extent_m = 0.03;            ///< half the side of the guide drawn, m
};

/// One scene.
struct Scene {
    std::string name;
    std::string description;
    std::vector<SceneBody> bodies;  ///< at least one; names unique
    DeviceMapping device_mapping;
    bool has_planned_cut = false;
    PlannedCut planned_cut;  ///< valid when has_planned_cut
};

/// Parses a scene from TOML text; `source_name` is used in error messages.
Result<Scene, ConfigError> parse_scene(std::string_view text, std::string_view source_name);

/// Reads and parses a scene file.
Result<Scene, ConfigError> load_scene(const std::filesystem::path& path);

/// Expands the variables in a kFile body's path (config/expand_path.hpp) and checks that the
/// file exists; errors are kBadReference naming the body and the path.
/// @pre body.mesh.kind == MeshSourceKind::kFile
Result<std::filesystem::path, ConfigError> resolve_mesh_path(const SceneBody& body,
                                                             const PathVars& vars);

}  // namespace kerf::config
