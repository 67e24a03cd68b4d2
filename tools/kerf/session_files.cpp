#include "tools/kerf/session_files.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "config/file_io/file_io.hpp"
#include "rt_core/ipc/session_socket.hpp"

namespace kerf::cli {
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
    auto bytes = files::read_regular_file(p, 64u << 20);
    if (!bytes) return {};
    return std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size());
}

bool write_file(const fs::path& p, const std::string& text) {
    const fs::path tmp = p.string() + ".tmp";
    {
        std::ofstream f(tmp, std::ios::trunc);
        f << text;
        if (!f.flush()) return false;
    }
    std::error_code ec;
    fs::rename(tmp, p, ec);
    return !ec;
}

std::string set_key(const std::string& text, const std::string& key, const std::string& value) {
    std::istringstream in(text);
    std::string line, out;
    while (std::getline(in, line)) {
        const auto first = line.find_first_not_of(' ');
        if (first != std::string::npos && line.compare(first, key.size() + 1, key + " ") == 0) {
            const auto hash = line.find('#');
            line =
                key + " = " + value + (hash == std::string::npos ? "" : "   " + line.substr(hash));
        }
        out += line + "\n";
    }
    return out;
}

double number_after(const std::string& text, const std::string& key) {
    const auto at = text.find(key);
    if (at == std::string::npos) return -1;
    return std::strtod(text.c_str() + at + key.size(), nullptr);
}

std::string json_string(const std::string& text, const std::string& key) {
    const auto at = text.find("\"" + key + "\": \"");
    if (at == std::string::npos) return {};
    const auto start = at + key.size() + 5;
    return text.substr(start, text.find('"', start) - start);
}

fs::path first_file(const fs::path& dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file()) return e.path();
    return {};
}

std::vector<std::string> remove_stale_sessions() {
    std::vector<std::string> removed;
    const std::string runtime = ipc::default_runtime_dir();
    for (const ipc::SessionEntry& e : ipc::list_session_dirs(runtime))
        if (e.has_socket && ipc::remove_stale_socket(runtime, e.name)) removed.push_back(e.name);
    return removed;
}

JournalPrune prune_journals(const fs::path& dir, const JournalBound& bound,
                            fs::file_time_type keep_since) {
    struct Entry {
        fs::path path;
        fs::file_time_type time;
        std::uint64_t bytes;
    };
    std::vector<Entry> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (!e.is_regular_file(ec) || e.path().extension() != ".kjournal") continue;
        files.push_back({e.path(), e.last_write_time(ec), e.file_size(ec)});
    }
    std::sort(files.begin(), files.end(),
              [](const Entry& a, const Entry& b) { return a.time > b.time; });  // newest first
    JournalPrune out;
    for (const Entry& f : files) {
        const bool current = f.time >= keep_since;
        if (current ||
            (out.kept < bound.max_files && out.kept_bytes + f.bytes <= bound.max_bytes)) {
            ++out.kept;
            out.kept_bytes += f.bytes;
        } else if (fs::remove(f.path, ec)) {
            ++out.removed;
        }
    }
    return out;
}

std::vector<std::string> display_args(const fs::path& bin, const DisplayLaunch& launch) {
    std::vector<std::string> args = {(bin / "kerf-display").string(), "--config",
                                     launch.config.string(), "--session", launch.session};
    if (!launch.mode.empty()) args.insert(args.end(), {"--mode", launch.mode});
    args.insert(args.end(), {"--status", launch.status.string()});
    if (launch.hash) args.push_back("--hash");
    if (!launch.screenshot.empty())
        args.insert(args.end(), {"--screenshot", launch.screenshot.string()});
    return args;
}

Result<WorkDir, std::string> WorkDir::create(const std::string& stem) {
    std::string templ =
        (fs::temp_directory_path() / (stem + "-" + std::to_string(getpid()) + "-XXXXXX")).string();
    if (!mkdtemp(templ.data()))
        return Err{"cannot create a temporary folder in " + fs::temp_directory_path().string()};
    return WorkDir(fs::path(templ));
}

WorkDir::~WorkDir() {
    if (path_.empty()) return;
    std::error_code ec;
    fs::remove_all(path_, ec);
}

}  // namespace kerf::cli
