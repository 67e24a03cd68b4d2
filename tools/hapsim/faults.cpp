#include "tools/hapsim/faults.hpp"

#include <charconv>

namespace kerf::hapsim {
namespace {

bool on_off(std::string_view value, bool& out) {
    if (value == "on" || value == "1") return (out = true, true);
    if (value == "off" || value == "0") return (out = false, true);
    return false;
}

bool count(std::string_view value, std::uint32_t& out) {
    if (value == "off") return (out = 0, true);
    const auto r = std::from_chars(value.data(), value.data() + value.size(), out);
    return r.ec == std::errc{} && r.ptr == value.data() + value.size() && out <= 60000;
}

}  // namespace

std::string apply_fault(Faults& f, std::string_view name, std::string_view value) {
    bool* flag = nullptr;
    if (name == "drop")
        flag = &f.drop;
    else if (name == "corrupt")
        flag = &f.corrupt;
    else if (name == "short")
        flag = &f.short_packets;
    else if (name == "unplug")
        flag = &f.unplugged;
    else if (name == "stuck_encoder")
        flag = &f.stuck_encoder;
    else if (name == "estop")
        flag = &f.estop;
    else if (name == "watchdog_trip")
        flag = &f.watchdog_trip;
    else if (name == "firmware_fail")
        flag = &f.firmware_fail;
    if (flag != nullptr) {
        if (!on_off(value, *flag))
            return "fault " + std::string(name) + ": value must be on or off";
        return {};
    }
    std::uint32_t n = 0;
    if (name == "delay") {
        if (!count(value, n)) return "fault delay: value must be milliseconds 0..60000 or off";
        f.delay_ms = n;
        return {};
    }
    if (name == "echo_mismatch") {
        if (!count(value, n)) return "fault echo_mismatch: value must be a chunk count or off";
        f.echo_mismatch_left = static_cast<int>(n);
        return {};
    }
    return "unknown fault '" + std::string(name) +
           "' (drop, delay, corrupt, short, unplug, stuck_encoder, estop, watchdog_trip, "
           "firmware_fail, echo_mismatch)";
}

}  // namespace kerf::hapsim
