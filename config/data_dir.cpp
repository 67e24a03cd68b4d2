#include "config/data_dir.hpp"

#include <cstdlib>
#include <system_error>

namespace kerf::config {
namespace fs = std::filesystem;

std::vector<fs::path> data_dir_candidates() {
    std::vector<fs::path> out;
    if (const char* env = std::getenv("KERF_DATA_DIR"); env != nullptr && env[0] != '\0')
        out.emplace_back(env);
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) out.push_back((self.parent_path() / ".." / "share" / "kerf").lexically_normal());
    out.emplace_back(KERF_SOURCE_DATA_DIR);
    out.emplace_back(KERF_INSTALL_DATA_DIR);
    return out;
}

fs::path data_dir() {
    std::error_code ec;
    for (const fs::path& dir : data_dir_candidates())
        if (fs::is_regular_file(dir / "kerf.toml", ec)) return dir;
    return fs::path(KERF_SOURCE_DATA_DIR);
}

fs::path data_file(std::string_view relative) { return data_dir() / relative; }

}  // namespace kerf::config
