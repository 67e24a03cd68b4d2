#include "tools/kerf/soak_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "tools/kerf/hand_script_writer.hpp"

namespace kerf::cli {
namespace {

constexpr double kPi = 3.14159265358979323846;

constexpr const char* kNames[kSoakFaultCount] = {
    "drop",  "delay",         "corrupt",      "short",        "unplug",
    "estop", "stuck-encoder", "display-kill", "display-stop", "scribble"};

using ScriptWriter = HandScriptWriter;

/// One limb: approach above `target`, tilt, press on the bone with the saw off, saw on, feed along
/// the blade through the bone until the edge is 4 mm below it (or the workspace's floor), saw off,
/// out below and round the side, back up, untilt. The plane crosses the target's mid-height at z =
/// target.z + dz.
PlannedCut cut_limb(ScriptWriter& w, const CutTarget& t, double dz, int steps, double feed,
                    const RoundScriptParams& p, const mesh::Point& origin, double side) {
    const double theta = steps * p.step_deg * kPi / 180.0;
    const mesh::Point v{0, std::cos(theta), std::sin(theta)};  // blade edge -> back
    const double mid_y = (t.top_y_m + t.bottom_y_m) / 2;
    const double floor_y = origin[1] - p.workspace_half_m + 0.006;
    const double end_y = std::max(t.bottom_y_m - 0.004, floor_y);
    const double start_y = t.top_y_m + 0.005;
    const mesh::Point mid{t.x_m, mid_y, t.z_m + dz};
    const mesh::Point end = w.clamped(mid - v * ((mid_y - end_y) / v[1]));
    const mesh::Point start = w.clamped(mid + v * ((start_y - mid_y) / v[1]));
    const mesh::Point approach = start + mesh::Point{0, 0.015, 0};
    const mesh::Point below = end - mesh::Point{0, 0.012, 0};
    const mesh::Point around = below + mesh::Point{side * (p.blade_length_m + 0.01), 0, 0};
    w.move(approach, 1.2);
    w.press(steps >= 0 ? 1 : 2, std::abs(steps));
    // The surgeon feels the bone first, saw off: the edge pressed 3 mm into the top for 2.5 s
    // (the device pushes back; the soak's device faults wait for a pushing tool).
    const mesh::Point touch{t.x_m, t.top_y_m - 0.003, mid[2] + (t.top_y_m - mid_y) * v[2] / v[1]};
    w.move(w.clamped(touch), 0.8);
    w.hold(2.5);
    w.move(start, 0.6);
    w.hold(0.2);
    w.button(0, true);  // saw on
    w.hold(0.3);
    PlannedCut cut;
    cut.tilt_deg = steps * p.step_deg;
    cut.feed_m_s = feed;
    cut.feed_start_s = w.time();
    w.move(end, std::max(0.5, (start - end).norm() / feed));
    cut.feed_end_s = w.time();
    w.button(0, false);  // saw off
    w.hold(2.0);         // the display opens the kerf and publishes the pieces
    w.move(below, 0.8);
    w.move(around, 0.8);
    w.move(around + mesh::Point{0, (t.top_y_m - end_y) + 0.03, 0}, 1.0);
    w.press(steps >= 0 ? 2 : 1, std::abs(steps));
    return cut;
}

}  // namespace

std::string_view to_string(SoakFault fault) noexcept {
    const auto i = static_cast<int>(fault);
    return i >= 0 && i < kSoakFaultCount ? kNames[i] : "?";
}

bool is_device_fault(SoakFault fault) noexcept { return fault <= SoakFault::kStuckEncoder; }

std::string hapsim_on_command(SoakFault fault) {
    switch (fault) {
        case SoakFault::kDelay:
            return "fault delay 50";
        case SoakFault::kStuckEncoder:
            return "fault stuck_encoder on";
        case SoakFault::kShort:
            return "fault short on";
        default:
            return "fault " + std::string(to_string(fault)) + " on";
    }
}

std::string hapsim_off_command(SoakFault fault) {
    std::string on = hapsim_on_command(fault);
    return on.substr(0, on.rfind(' ')) + " off";
}

Result<std::vector<SoakFault>, std::string> parse_fault_list(const std::string& list) {
    std::vector<SoakFault> out;
    if (list == "none") return out;
    if (list == "all") {
        for (int i = 0; i < kSoakFaultCount; ++i) out.push_back(static_cast<SoakFault>(i));
        return out;
    }
    std::size_t at = 0;
    while (at <= list.size()) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        const std::string name = list.substr(at, comma - at);
        int found = -1;
        for (int i = 0; i < kSoakFaultCount; ++i)
            if (name == kNames[i]) found = i;
        if (found < 0) {
            std::string known;
            for (const char* n : kNames) known += std::string(known.empty() ? "" : ", ") + n;
            return Err{"unknown fault '" + name + "' (all, none, or a list of: " + known + ")"};
        }
        if (std::find(out.begin(), out.end(), SoakFault(found)) == out.end())
            out.push_back(SoakFault(found));
        at = comma + 1;
    }
    return out;
}

Result<RoundScript, std::string> make_round_script(const std::vector<CutTarget>& targets,
                                                   const mesh::Point& origin, std::uint64_t seed,
                                                   const RoundScriptParams& p) {
    if (targets.empty()) return Err{std::string("no bone to cut")};
    std::mt19937_64 rng(seed);
    const auto uniform = [&](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    const int max_steps = static_cast<int>(std::lround(p.max_tilt_deg / p.step_deg));
    ScriptWriter w(origin, p.workspace_half_m - 0.004);
    RoundScript out;
    w.hold(p.start_hold_s);
    double last_s = 0;  // how long the previous scenario took: the next one takes about as long
    while (out.cuts.empty() || w.time() + last_s / 2 <= p.duration_s) {
        const double started = w.time();
        const CutTarget& t = targets[rng() % targets.size()];
        const double feed = uniform(p.feed_min_m_s, p.feed_max_m_s);
        const double side = rng() % 2 ? 1.0 : -1.0;
        const int kind = static_cast<int>(rng() % 3);
        if (kind == 0) {  // one plane, tilted at random
            const int steps = static_cast<int>(rng() % (2 * max_steps + 1)) - max_steps;
            out.cuts.push_back(cut_limb(w, t, 0, steps, feed, p, origin, side));
            out.cuts.back().kind = "plane";
        } else if (kind == 1) {  // a chevron: two limbs either side, meeting below the bone
            const int steps = 2 + static_cast<int>(rng() % std::max(1, max_steps - 1));
            const double half_h = (t.top_y_m - t.bottom_y_m) / 2 + 0.004;
            const double apex_dz = 0.0;
            for (const int sign : {+1, -1}) {
                const double tan_t = std::tan(steps * p.step_deg * kPi / 180.0);
                out.cuts.push_back(cut_limb(w, t, apex_dz + sign * half_h * tan_t, sign * steps,
                                            feed, p, origin, side));
                out.cuts.back().kind = "chevron limb";
            }
        } else {  // a slab: two parallel planes 3..8 mm apart
            const int steps = static_cast<int>(rng() % (2 * max_steps + 1)) - max_steps;
            const double gap = uniform(0.003, 0.008);
            for (const double dz : {-gap / 2, gap / 2}) {
                out.cuts.push_back(cut_limb(w, t, dz, steps, feed, p, origin, side));
                out.cuts.back().kind = "slab face";
            }
        }
        last_s = w.time() - started;
    }
    w.move(origin, 1.0);  // home
    w.hold(1.0);
    out.csv = w.text();
    out.duration_s = w.time();
    return out;
}

}  // namespace kerf::cli
