// Small helpers shared by the firmware_host tests: byte buffers, fixture files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace kerf::firmware_host::test {

inline std::filesystem::path fixture_dir() {
    return std::filesystem::path(KERF_SOURCE_DIR) / "tests/firmware_host/fixtures";
}

inline std::vector<std::byte> read_bytes(const std::filesystem::path& path) {
    std::ifstream f(path, std::ios::binary);
    std::vector<char> raw((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    std::vector<std::byte> out(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) out[i] = static_cast<std::byte>(raw[i]);
    return out;
}

inline void write_bytes(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

template <std::size_t N>
std::array<char, N> fixed(const std::string& s) {
    std::array<char, N> out{};
    for (std::size_t i = 0; i < s.size() && i < N; ++i) out[i] = s[i];
    return out;
}

}  // namespace kerf::firmware_host::test
