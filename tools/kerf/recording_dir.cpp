#include "tools/kerf/recording_dir.hpp"

#include <algorithm>
#include <cstring>

#include "config/device_profile.hpp"
#include "config/expand_path.hpp"
#include "config/load_config.hpp"
#include "rt_core/ipc/journal_reader.hpp"
#include "tools/kerf/session_files.hpp"

namespace kerf::cli {
namespace fs = std::filesystem;

namespace {

Result<bool, std::string> copy_file_atomic(const fs::path& from, const fs::path& to) {
    std::error_code ec;
    const fs::path tmp = to.string() + ".tmp";
    fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, ec);
    if (!ec) fs::rename(tmp, to, ec);
    if (ec) {
        fs::remove(tmp, ec);
        return Err{"copy of " + from.string() + " to " + to.string() + ": " + ec.message()};
    }
    return true;
}

/// `file` relative to `dir` when it lies inside it, else empty.
fs::path inside(const fs::path& file, const fs::path& dir) {
    const fs::path rel = file.lexically_normal().lexically_relative(dir.lexically_normal());
    if (rel.empty() || *rel.begin() == "..") return {};
    return rel;
}

/// Why a recording can hold fewer records than its session's ticks.
constexpr const char* kUnrecordedReopen =
    "the input stream stops there. Format 3 recordings (kerf-rt records from inside its loop) "
    "hold every tick, a lost and re-opened device included; a format 2 recording stops where "
    "the device was lost (unplugged?), and a cut-short file lost its end: either way the "
    "session cannot be replayed past that tick";

}  // namespace

std::uint64_t input_records(const fs::path& input) {
    std::error_code ec;
    const auto size = fs::file_size(input, ec);
    return ec || size < 64 ? 0 : (size - 64) / 128;  // RecordingHeader, RecordedInput
}

std::string recording_gap(const fs::path& input, std::uint64_t ticks) {
    const std::uint64_t records = input_records(input);
    if (records >= ticks) return {};
    return "only " + std::to_string(records) + " of " + std::to_string(ticks) +
           " ticks recorded: " + kUnrecordedReopen;
}

Result<std::vector<fs::path>, std::string> session_config_files(const fs::path& config_dir,
                                                                const std::string& device) {
    auto cfg = config::load_config(config_dir / "kerf.toml");
    if (!cfg) return Err{cfg.error().message()};
    const config::ProfileNames& names = cfg->main.profiles;
    std::vector<fs::path> files = {"kerf.toml", fs::path("devices") / (names.device + ".toml"),
                                   fs::path("force") / (names.force + ".toml"),
                                   fs::path("scenes") / (names.scene + ".toml")};
    if (!device.empty())
        files.push_back(fs::path("devices") /
                        (std::string(config::device_profile_stem(device)) + ".toml"));
    for (const config::SceneBody& body : cfg->scene.bodies) {
        if (body.mesh.kind != config::MeshSourceKind::kFile) continue;
        auto path = config::expand_path(body.mesh.path, config::path_vars(*cfg));
        if (!path) return Err{path.error().message()};
        if (fs::path rel = inside(*path, cfg->config_dir); !rel.empty()) files.push_back(rel);
    }
    std::sort(files.begin(), files.end());
    files.erase(std::unique(files.begin(), files.end()), files.end());
    return files;
}

Result<std::vector<std::pair<fs::path, fs::path>>, std::string> shared_scene_files(
    const fs::path& config_dir) {
    auto cfg = config::load_config(config_dir / "kerf.toml");
    if (!cfg) return Err{cfg.error().message()};
    const config::PathVars vars = config::path_vars(*cfg);
    std::vector<std::pair<fs::path, fs::path>> out;
    for (const config::SceneBody& body : cfg->scene.bodies) {
        if (body.mesh.kind != config::MeshSourceKind::kFile) continue;
        auto path = config::expand_path(body.mesh.path, vars);
        if (!path) return Err{path.error().message()};
        if (!inside(*path, cfg->config_dir).empty()) continue;  // kept with the config
        if (fs::path rel = inside(*path, vars.shared_dir); !rel.empty())
            out.emplace_back(*path, rel);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

Result<bool, std::string> save_recording(const fs::path& dir, const fs::path& config_dir,
                                         const fs::path& input, const fs::path& journal,
                                         const fs::path& trace, const nlohmann::json& meta) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return Err{"recording folder " + dir.string() + ": " + ec.message()};
    // kerf.toml and what it names, not the whole folder (an installed or source config folder
    // holds every profile, udev rules, and in the source tree the config library's code).
    const std::string device = meta.contains("device") && meta["device"].is_string()
                                   ? meta["device"].get<std::string>()
                                   : std::string();
    auto files = session_config_files(config_dir, device);
    if (!files) return Err{"configuration " + config_dir.string() + ": " + files.error()};
    fs::remove_all(dir / "config", ec);
    for (const fs::path& rel : *files) {
        fs::create_directories((dir / "config" / rel).parent_path(), ec);
        if (ec) return Err{"recording folder " + (dir / "config").string() + ": " + ec.message()};
        if (auto copied = copy_file_atomic(config_dir / rel, dir / "config" / rel); !copied)
            return Err{copied.error()};
    }
    // Scene meshes from the shared folder (${shared}/meshes/...) go into DIR/shared/ at the same
    // relative path, so the recording replays on a machine without that folder (kerf replay
    // points ${shared} there).
    fs::remove_all(dir / "shared", ec);
    auto shared = shared_scene_files(config_dir);
    if (!shared) return Err{"configuration " + config_dir.string() + ": " + shared.error()};
    for (const auto& [from, rel] : *shared) {
        fs::create_directories((dir / "shared" / rel).parent_path(), ec);
        if (ec) return Err{"recording folder " + (dir / "shared").string() + ": " + ec.message()};
        if (auto copied = copy_file_atomic(from, dir / "shared" / rel); !copied)
            return Err{copied.error()};
    }
    for (const auto& [from, name] :
         {std::pair{input, "input.rec"}, std::pair{journal, "session.journal"},
          std::pair{trace, "force-trace.csv"}}) {
        if (from.empty() || !fs::exists(from)) continue;
        if (auto copied = copy_file_atomic(from, dir / name); !copied) return Err{copied.error()};
    }
    if (!write_file(dir / "recording.json", meta.dump(2) + "\n"))
        return Err{"cannot write " + (dir / "recording.json").string()};
    return true;
}

Result<nlohmann::json, std::string> load_recording_meta(const fs::path& dir) {
    const fs::path file = dir / "recording.json";
    if (!fs::is_regular_file(file))
        return Err{file.string() + ": not found (record with kerf run --record DIR or kerf demo)"};
    auto meta = nlohmann::json::parse(slurp(file), nullptr, false);
    if (meta.is_discarded() || !meta.is_object()) return Err{file.string() + ": not valid JSON"};
    for (const char* key : {"device", "ticks", "events", "hash"})
        if (!meta.contains(key)) return Err{file.string() + ": no \"" + key + "\""};
    if (!meta["device"].is_string() || !meta["hash"].is_string() ||
        !meta["ticks"].is_number_unsigned() || !meta["events"].is_number_unsigned())
        return Err{file.string() + ": device/hash must be strings, ticks/events counts"};
    for (const char* f : {"input.rec", "session.journal", "config/kerf.toml"})
        if (!fs::is_regular_file(dir / f)) return Err{(dir / f).string() + ": missing"};
    const std::uint64_t ticks = meta["ticks"].get<std::uint64_t>();
    if (const std::uint64_t records = input_records(dir / "input.rec"); records < ticks)
        return Err{(dir / "input.rec").string() + ": " + std::to_string(records) + " of the " +
                   std::to_string(ticks) + " ticks recorded: " + kUnrecordedReopen};
    return meta;
}

Result<JournalComparison, std::string> compare_journals(const fs::path& a, const fs::path& b) {
    auto ra = ipc::JournalReader::open(a.string(), 0);
    if (!ra) return Err{a.string() + ": " + ra.error().message()};
    auto rb = ipc::JournalReader::open(b.string(), 0);
    if (!rb) return Err{b.string() + ": " + rb.error().message()};
    JournalComparison out;
    out.records_a = ra->record_count();
    out.records_b = rb->record_count();
    const std::uint64_t n = std::min(out.records_a, out.records_b);
    for (std::uint64_t s = 0; s < n; ++s) {
        ipc::EventRecord x{}, y{};
        const bool ok = ra->try_read(s, x) == ipc::JournalRead::kOk &&
                        rb->try_read(s, y) == ipc::JournalRead::kOk;
        const bool same = ok && x.header.sequence == y.header.sequence &&
                          x.header.type == y.header.type &&
                          std::memcmp(reinterpret_cast<const char*>(&x) + sizeof x.header,
                                      reinterpret_cast<const char*>(&y) + sizeof y.header,
                                      sizeof x - sizeof x.header) == 0;
        if (!same) {
            out.first_difference = s;
            return out;
        }
    }
    out.first_difference = n;
    out.equal = out.records_a == out.records_b;
    return out;
}

}  // namespace kerf::cli
