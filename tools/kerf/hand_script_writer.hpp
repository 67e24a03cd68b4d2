// Writes a kerf-hapsim hand script (CSV, tools/hapsim/README.md) from world-frame positions: the
// device origin maps to `device_origin_world_m` (kerf-rt's mapping: scale 1, no rotation), and
// positions may be clamped into the device's workspace. Keeps the script's clock. Used by the
// demo's and the soak's scripted surgeons. Units: m, s.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cli {

class HandScriptWriter {
public:
    /// `clamp_half_m`: every move is clamped to +- this around the origin, each axis.
    explicit HandScriptWriter(const mesh::Point& device_origin_world_m,
                              double clamp_half_m = std::numeric_limits<double>::infinity())
        : origin_(device_origin_world_m), half_(clamp_half_m) {}

    /// Holds still for `s` seconds.
    void hold(double s) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "hold,%.4f\n", s);
        text_ += buf;
        t_ += s;
    }
    /// Moves the blade's edge centre to `world` (clamped) in `s` seconds.
    void move(const mesh::Point& world, double s) {
        const mesh::Point d = clamped(world) - origin_;
        char buf[160];
        std::snprintf(buf, sizeof buf, "move,%.6f,%.6f,%.6f,%.4f\n", d[0], d[1], d[2], s);
        text_ += buf;
        t_ += s;
        for (int i = 0; i < 3; ++i) max_abs_ = std::max(max_abs_, std::abs(d[i]));
    }
    /// Presses (`down`) or releases button `b`.
    void button(int b, bool down) {
        text_ += "button," + std::to_string(b) + (down ? ",down\n" : ",up\n");
    }
    /// `count` presses of button `b`, 50 ms down, 50 ms up.
    void press(int b, int count) {
        for (int i = 0; i < count; ++i) {
            button(b, true);
            hold(0.05);
            button(b, false);
            hold(0.05);
        }
    }
    /// The world point a move to `world` goes to (inside the clamp box).
    mesh::Point clamped(const mesh::Point& world) const {
        mesh::Point d = world - origin_;
        for (int i = 0; i < 3; ++i) d[i] = std::clamp(d[i], -half_, half_);
        return origin_ + d;
    }
    double time() const { return t_; }                 ///< script time so far, s
    double max_abs() const { return max_abs_; }        ///< farthest a move went on one axis, m
    const std::string& text() const { return text_; }  ///< the script

private:
    mesh::Point origin_;
    double half_;
    std::string text_;
    double t_ = 0;
    double max_abs_ = 0;
};

}  // namespace kerf::cli
