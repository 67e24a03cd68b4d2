// config::data_dir: $KERF_DATA_DIR first when it holds a kerf.toml; else (in a build tree, not
// installed) the source tree's config/.
#include "config/data_dir.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;

struct EnvGuard {
    EnvGuard() { unsetenv("KERF_DATA_DIR"); }
    ~EnvGuard() { unsetenv("KERF_DATA_DIR"); }
};

TEST(DataDir, EnvironmentWinsWhenItHoldsKerfToml) {
    EnvGuard guard;
    const fs::path dir = fs::temp_directory_path() / ("kerf-data-dir-" + std::to_string(getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "kerf.toml") << "# test\n";
    setenv("KERF_DATA_DIR", dir.c_str(), 1);
    EXPECT_EQ(kerf::config::data_dir(), dir);
    EXPECT_EQ(kerf::config::data_file("devices/simulated.toml"), dir / "devices/simulated.toml");
    EXPECT_EQ(kerf::config::data_dir_candidates().front(), dir);
    fs::remove_all(dir);
}

TEST(DataDir, EnvironmentWithoutKerfTomlFallsBackToTheSourceTree) {
    EnvGuard guard;
    setenv("KERF_DATA_DIR", "/nonexistent-kerf-data", 1);
    // The test binary is not installed (no share/kerf beside it): the source tree's config/.
    EXPECT_EQ(fs::canonical(kerf::config::data_dir()),
              fs::canonical(fs::path(KERF_SOURCE_DIR) / "config"));
    EXPECT_TRUE(fs::is_regular_file(kerf::config::data_file("kerf.toml")));
    EXPECT_EQ(kerf::config::data_dir_candidates().size(), 4u);
}

}  // namespace
