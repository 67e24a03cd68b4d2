// libFuzzer target: the kerf-hapsim hand-script parser over arbitrary text, then a short play.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "tools/hapsim/hand_script.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto script = kerf::hapsim::parse_hand_script(text, "fuzz");
    if (!script) return 0;
    kerf::hapsim::HandPlayer hand(*script, {0, 0, 0});
    std::vector<kerf::hapsim::FaultEvent> events;
    for (double t = 0; t < 2.0; t += 0.1) hand.advance(t, events);
    return 0;
}
