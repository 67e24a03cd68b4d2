// Helpers shared by the config tests: the shipped files as text, edits on them, and a scratch
// copy of the config folder for tests that change kerf.toml or add profiles.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "config/config_error.hpp"

namespace kerf::config {
/// Lets gtest print error kinds by name.
inline void PrintTo(ConfigErrc kind, std::ostream* os) { *os << to_string(kind); }
}  // namespace kerf::config

namespace kerf::config::test {

inline const std::filesystem::path kConfigDir = std::filesystem::path(KERF_SOURCE_DIR) / "config";

/// The text of a shipped file, e.g. shipped("force/default.toml").
inline std::string shipped(const std::string& relative) {
    std::ifstream in(kConfigDir / relative, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// `text` with the first occurrence of `from` replaced by `to`; fails the test if absent.
inline std::string edit(std::string text, std::string_view from, std::string_view to) {
    auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the text";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

/// 1-based line of the first occurrence of `needle` in `text` (0 when absent).
inline std::uint32_t line_of(std::string_view text, std::string_view needle) {
    auto at = text.find(needle);
    if (at == std::string_view::npos) return 0;
    std::uint32_t line = 1;
    for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n' ? 1 : 0;
    return line;
}

/// The error of a result that must have failed (a default error if it did not).
template <class R>
ConfigError error_of(const R& r) {
    EXPECT_FALSE(r) << "expected the parse to fail";
    return r ? ConfigError{} : r.error();
}

/// A fresh copy of the shipped config folder's TOML files in a scratch directory.
inline std::filesystem::path scratch_config_copy(const std::string& name) {
    namespace fs = std::filesystem;
    fs::path dir = fs::path(testing::TempDir()) / ("kerf_config_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(kConfigDir / "kerf.toml", dir / "kerf.toml");
    for (const char* sub : {"devices", "force", "scenes"})
        fs::copy(kConfigDir / sub, dir / sub, fs::copy_options::recursive);
    return dir;
}

inline void write_file(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

}  // namespace kerf::config::test
