#include "config/scene.hpp"

#include <cmath>
#include <system_error>

#include "config/toml_reader.hpp"
#include "display/mesh/foot_range.hpp"

namespace kerf::config {
namespace {

using detail::closed;
using detail::TableReader;

// The accepted `units` names, in kLengthUnits' order ("m", "cm", "mm", "um", "in").
const std::vector<std::string_view> kUnitNames = [] {
    std::vector<std::string_view> names;
    for (const LengthUnit unit : kLengthUnits) names.push_back(to_string(unit));
    return names;
}();
const std::vector<std::string_view> kMaterialNames = {"cortical", "cancellous"};
const std::vector<std::string_view> kSourceNames = {"file", "builtin_foot"};

constexpr double kPi = 3.14159265358979323846;
constexpr double kQuaternionTolerance = 1e-3;
// The generator's own range: a scene that loads is a scene the generator builds.
constexpr auto kMinTriangles = static_cast<std::int64_t>(mesh::kFootMinTriangles);
constexpr auto kMaxTriangles = static_cast<std::int64_t>(mesh::kFootMaxTriangles);

void read_mesh(TableReader m, MeshSource& out) {
    auto source = m.choice("source", kSourceNames);
    out.kind = source == 0 ? MeshSourceKind::kFile : MeshSourceKind::kBuiltinFoot;
    if (out.kind == MeshSourceKind::kFile) {
        out.path = m.string("path");
        std::string bad;
        if (m.has("path") && out.path.empty()) {
            m.fail("path", ConfigErrc::kBadValue, "a non-empty path");
        } else if (!check_path_template(out.path, &bad)) {
            m.fail("path", ConfigErrc::kBadReference,
                   "a path; variables ${config}, ${shared}, ${tmp}, ${runtime}",
                   "cannot expand " + bad);
        }
        out.units = kLengthUnits[m.choice("units", kUnitNames, ConfigErrc::kBadUnit)];
        for (auto key : {"target_triangles", "seed"})
            m.forbid(key, "only for source = \"builtin_foot\"");
    } else {
        out.target_triangles =
            static_cast<std::uint64_t>(m.integer("target_triangles", kMinTriangles, kMaxTriangles));
        out.seed = static_cast<std::uint64_t>(m.integer("seed", 0, INT64_MAX));
        out.units = LengthUnit::kMetre;
        for (auto key : {"path", "units"}) m.forbid(key, "only for source = \"file\"");
    }
}

std::array<double, 4> axis_angle(TableReader& t) {
    auto axis = t.numbers<3>("rotation_axis", closed(-1e6, 1e6, ""));
    double angle_deg = t.number("rotation_angle_deg", closed(-360, 360, "deg"));
    double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if (norm < 1e-12) {
        if (t.problems().empty())
            t.fail("rotation_axis", ConfigErrc::kOutOfRange, "a non-zero axis");
        return {1, 0, 0, 0};
    }
    double half = angle_deg * kPi / 360.0;
    double s = std::sin(half) / norm;
    return {std::cos(half), axis[0] * s, axis[1] * s, axis[2] * s};
}

std::array<double, 4> quaternion(TableReader& t) {
    auto q = t.numbers<4>("rotation_quaternion_wxyz", closed(-1.01, 1.01, ""));
    double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (std::abs(norm - 1.0) > kQuaternionTolerance) {
        if (t.problems().empty())
            t.fail("rotation_quaternion_wxyz", ConfigErrc::kOutOfRange,
                   "a unit quaternion [w, x, y, z] (|q| = 1 +- 0.001)",
                   "|q| = " + detail::format_number(norm));
        return {1, 0, 0, 0};
    }
    return {q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm};
}

/// rotation_axis + rotation_angle_deg, or rotation_quaternion_wxyz, or neither (identity).
void read_rotation(TableReader& t, std::array<double, 4>& out) {
    bool quat = t.has("rotation_quaternion_wxyz");
    bool axis = t.has("rotation_axis") || t.has("rotation_angle_deg");
    for (auto key : {"rotation_axis", "rotation_angle_deg", "rotation_quaternion_wxyz"})
        t.problems().mark_known(&t.raw(), key);
    if (quat && axis) {
        t.fail("rotation_quaternion_wxyz", ConfigErrc::kBadValue, "",
               "write the rotation once: rotation_axis + rotation_angle_deg, or "
               "rotation_quaternion_wxyz");
        return;
    }
    if (quat) out = quaternion(t);
    if (axis) out = axis_angle(t);
}

void read_transform(TableReader t, RigidTransform& out) {
    if (t.has("translation_m"))
        out.translation_m = t.numbers<3>("translation_m", closed(-10, 10, "m"));
    else
        t.problems().mark_known(&t.raw(), "translation_m");
    read_rotation(t, out.rotation_wxyz);
}

void read_device_mapping(TableReader t, DeviceMapping& out) {
    out.origin_given = t.has("origin_m");
    if (out.origin_given)
        out.origin_m = t.numbers<3>("origin_m", closed(-10, 10, "m"));
    else
        t.problems().mark_known(&t.raw(), "origin_m");
    out.scale = t.number_or("scale", 1.0, closed(0.1, 10, ""));
    read_rotation(t, out.rotation_wxyz);
}

/// `key` as a unit vector (any non-zero length is accepted and normalised).
std::array<double, 3> unit_vector(TableReader& t, std::string_view key) {
    auto v = t.numbers<3>(key, closed(-1e6, 1e6, ""));
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n < 1e-9) {
        if (t.problems().empty()) t.fail(key, ConfigErrc::kOutOfRange, "a non-zero vector");
        return {0, 0, 1};
    }
    return {v[0] / n, v[1] / n, v[2] / n};
}

void read_planned_cut(TableReader t, PlannedCut& out) {
    out.point_m = t.numbers<3>("point_m", closed(-10, 10, "m"));
    out.normal = unit_vector(t, "normal");
    out.half_extent_m = t.number_or("half_extent_m", 0.03, closed(0.001, 1, "m"));
    const auto& n = out.normal;
    std::array<double, 3> e{};
    if (t.has("edge")) {
        e = unit_vector(t, "edge");
    } else {  // the world axis least aligned with the normal
        t.problems().mark_known(&t.raw(), "edge");
        const std::size_t axis = std::abs(n[0]) <= std::abs(n[1])
                                     ? (std::abs(n[0]) <= std::abs(n[2]) ? 0 : 2)
                                     : (std::abs(n[1]) <= std::abs(n[2]) ? 1 : 2);
        e[axis] = 1.0;
    }
    const double d = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
    std::array<double, 3> u{e[0] - d * n[0], e[1] - d * n[1], e[2] - d * n[2]};
    const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (len < 0.1) {  // within ~6 degrees of the normal: not a direction in the plane
        if (t.problems().empty())
            t.fail("edge", ConfigErrc::kBadValue,
                   "a direction in the plane (at least 6 degrees off the normal)");
        return;
    }
    out.edge = {u[0] / len, u[1] / len, u[2] / len};
}

SceneBody read_body(TableReader b) {
    SceneBody body;
    body.name = b.string("name");
    body.material = static_cast<BodyMaterial>(b.choice_or("material", 0, kMaterialNames));
    read_mesh(b.table("mesh"), body.mesh);
    read_transform(b.table("transform", false), body.transform);
    return body;
}

Scene read_scene(TableReader& root) {
    Scene s;
    s.name = root.string("name");
    s.description = root.string_or("description", "");
    auto bodies = root.tables("bodies");
    if (bodies.empty() && root.has("bodies"))
        root.fail("bodies", ConfigErrc::kOutOfRange, "at least one [[bodies]] table");
    read_device_mapping(root.table("device_mapping", false), s.device_mapping);
    s.has_planned_cut = root.has("planned_cut");
    if (s.has_planned_cut) read_planned_cut(root.table("planned_cut"), s.planned_cut);
    for (auto& b : bodies) {
        s.bodies.push_back(read_body(b));
        const std::string& name = s.bodies.back().name;
        for (std::size_t i = 0; i + 1 < s.bodies.size(); ++i) {
            if (!name.empty() && s.bodies[i].name == name) {
                b.fail("name", ConfigErrc::kBadValue, "a name unique within the scene",
                       "body " + std::to_string(i) + " has the same name");
            }
        }
    }
    return s;
}

}  // namespace

std::string_view to_string(BodyMaterial material) noexcept {
    return material == BodyMaterial::kCortical ? "cortical" : "cancellous";
}

std::string_view to_string(MeshSourceKind kind) noexcept {
    return kind == MeshSourceKind::kFile ? "file" : "builtin_foot";
}

Result<Scene, ConfigError> parse_scene(std::string_view text, std::string_view source_name) {
    return detail::parse_document<Scene>(text, source_name, read_scene);
}

Result<Scene, ConfigError> load_scene(const std::filesystem::path& path) {
    auto text = detail::read_text_file(path.string());
    if (!text) return Err{text.error()};
    return parse_scene(*text, path.string());
}

Result<std::filesystem::path, ConfigError> resolve_mesh_path(const SceneBody& body,
                                                             const PathVars& vars) {
    auto path = expand_path(body.mesh.path, vars);
    if (!path) {
        ConfigError e = path.error();
        e.key = "bodies." + body.name + ".mesh.path";
        return Err{described(e)};
    }
    std::error_code ec;
    if (!std::filesystem::is_regular_file(*path, ec)) {
        ConfigError e;
        e.code = ConfigErrc::kBadReference;
        e.key = "bodies." + body.name + ".mesh.path";
        e.value = "\"" + body.mesh.path + "\"";
        e.expected = "an existing mesh file";
        e.note = "no such file: " + path->string();
        return Err{described(e)};
    }
    return *path;
}

}  // namespace kerf::config
