#include "config/load_config.hpp"

#include <algorithm>
#include <system_error>
#include <utility>

#include "config/toml_reader.hpp"

namespace kerf::config {
namespace {

namespace fs = std::filesystem;

/// Fills in the file position of `key` in `file` (re-read; config files are small).
ConfigError located(ConfigError e, const fs::path& file, std::string_view key) {
    e.source = file.string();
    auto text = detail::read_text_file(file.string());
    if (!text) return described(e);
    auto doc = detail::parse_toml(*text, e.source);
    if (!doc) return described(e);
    toml::node_view<const toml::node> node = std::as_const(*doc).at_path(key);
    if (node) {
        e.line = node.node()->source().begin.line;
        e.column = node.node()->source().begin.column;
    }
    return described(e);
}

/// The profile names available in `dir` (file stems of *.toml), sorted, comma-separated.
std::string available_names(const fs::path& dir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->path().extension() == ".toml") names.push_back(it->path().stem().string());
    }
    std::sort(names.begin(), names.end());
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s.empty() ? "(none: the folder is empty or missing)" : s;
}

/// `<config_dir>/<folder>/<name>.toml`, or a kBadReference error located at `key` of kerf.toml.
Result<fs::path, ConfigError> profile_path(const fs::path& kerf_toml, std::string_view folder,
                                           const std::string& name, std::string_view key) {
    fs::path dir = kerf_toml.parent_path() / folder;
    fs::path file = dir / (name + ".toml");
    std::error_code ec;
    // Whatever is there is returned, so that reading it says what it is (a FIFO, a directory,
    // a device) instead of "no file".
    if (fs::exists(file, ec)) return file;
    ConfigError e;
    e.code = ConfigErrc::kBadReference;
    e.key = std::string(key);
    e.value = "\"" + name + "\"";
    e.expected = "one of: " + available_names(dir);
    e.note = "no file " + std::string(folder) + "/" + name + ".toml";
    return Err{located(e, kerf_toml, key)};
}

/// Every file-backed body's mesh must exist.
Status<ConfigError> check_meshes(const Config& c, const fs::path& scene_file) {
    for (std::size_t i = 0; i < c.scene.bodies.size(); ++i) {
        const SceneBody& body = c.scene.bodies[i];
        if (body.mesh.kind != MeshSourceKind::kFile) continue;
        auto path = resolve_mesh_path(body, path_vars(c));
        if (!path) {
            std::string key = "bodies[" + std::to_string(i) + "].mesh.path";
            ConfigError e = path.error();
            e.key = key;
            return Err{located(e, scene_file, key)};
        }
    }
    return {};
}

/// A profile loaded from `<config_dir>/<folder>/<name>.toml`, and the file it came from.
template <class T>
struct Loaded {
    T value;
    fs::path file;
};

template <class T, class Load>
Result<Loaded<T>, ConfigError> load_named(const fs::path& main_file, std::string_view folder,
                                          const std::string& name, std::string_view key,
                                          Load load) {
    auto file = profile_path(main_file, folder, name, key);
    if (!file) return Err{file.error()};
    auto value = load(*file);
    if (!value) return Err{value.error()};
    return Loaded<T>{std::move(*value), *file};
}

/// kerf.toml itself, with its folders expanded.
Result<Config, ConfigError> load_main(const fs::path& main_file) {
    Config c;
    c.config_dir = main_file.parent_path();
    auto main = load_kerf_config(main_file);
    if (!main) return Err{main.error()};
    c.main = std::move(*main);
    auto shared = expand_path(c.main.shared_dir, {c.config_dir, {}});
    if (!shared) return Err{located(shared.error(), main_file, "paths.shared")};
    c.shared_dir = *shared;
    auto journal = expand_path(c.main.journal.dir, path_vars(c));
    if (!journal) return Err{located(journal.error(), main_file, "journal.dir")};
    c.journal_dir = *journal;
    return c;
}

/// The force profile may not ask for more than the device can give.
Status<ConfigError> check_force_within_device(const Config& c, const fs::path& force_file,
                                              const fs::path& device_file) {
    if (c.force.limits.max_force_n <= c.device.limits.peak_force_n) return {};
    ConfigError e;
    e.code = ConfigErrc::kOutOfRange;
    e.key = "limits.max_force_n";
    e.value = detail::format_number(c.force.limits.max_force_n);
    e.expected = "<= the device's peak_force_n (" +
                 detail::format_number(c.device.limits.peak_force_n) + " N in " +
                 device_file.string() + ")";
    return Err{located(e, force_file, e.key)};
}

}  // namespace

PathVars path_vars(const Config& config) { return {config.config_dir, config.shared_dir}; }

Result<Config, ConfigError> load_config(const fs::path& kerf_toml) {
    std::error_code ec;
    fs::path main_file = fs::absolute(kerf_toml, ec).lexically_normal();
    if (ec) main_file = kerf_toml;
    auto c = load_main(main_file);
    if (!c) return c;
    const ProfileNames& names = c->main.profiles;
    auto device = load_named<DeviceProfile>(main_file, "devices", names.device, "profiles.device",
                                            load_device_profile);
    if (!device) return Err{device.error()};
    auto force = load_named<ForceProfile>(main_file, "force", names.force, "profiles.force",
                                          load_force_profile);
    if (!force) return Err{force.error()};
    auto scene = load_named<Scene>(main_file, "scenes", names.scene, "profiles.scene", load_scene);
    if (!scene) return Err{scene.error()};
    c->device = std::move(device->value);
    c->force = std::move(force->value);
    c->scene = std::move(scene->value);
    if (auto s = check_force_within_device(*c, force->file, device->file); !s)
        return Err{s.error()};
    if (auto s = check_meshes(*c, scene->file); !s) return Err{s.error()};
    return c;
}

}  // namespace kerf::config
