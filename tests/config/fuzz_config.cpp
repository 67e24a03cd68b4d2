// libFuzzer target: arbitrary text through every kerf_config parser. Properties checked beyond
// "no crash, no sanitizer report": every failure has a non-empty message naming the source, and
// a force profile the parser accepts passes the live-reload validator (the two agree).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "config/device_profile.hpp"
#include "config/force_profile.hpp"
#include "config/kerf_config.hpp"
#include "config/scene.hpp"

namespace {

template <class R>
void check_result(const R& r) {
    if (r) return;
    std::string m = r.error().message();
    if (m.rfind("fuzz.toml", 0) != 0) __builtin_trap();  // every error names its source first
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace kerf::config;
    std::string_view text(reinterpret_cast<const char*>(data), size);
    check_result(parse_kerf_config(text, "fuzz.toml"));
    check_result(parse_device_profile(text, "fuzz.toml"));
    check_result(parse_scene(text, "fuzz.toml"));
    auto force = parse_force_profile(text, "fuzz.toml");
    check_result(force);
    if (force && !validate_force_profile(*force).empty()) __builtin_trap();
    return 0;
}
