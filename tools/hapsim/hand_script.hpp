// The scripted hand: a CSV script of actions run one after another, giving the hand's target
// position and velocity, its buttons, and fault events at scripted times. Units: m, s.
//
//   # action,args...                 (blank lines and # comments allowed)
//   move,0.01,0.0,0.11,0.5           # to x,y,z (m) in 0.5 s (straight line, constant speed)
//   hold,0.2                         # stay 0.2 s
//   button,0,down                    # press (or release: up) button 0..15
//   sweep,0.02,0,0,2.0,1.5           # sinusoid of amplitude vector (m) at 2 Hz for 1.5 s
//   fault,drop,on                    # inject a fault (see faults.hpp); off to clear
//   orient,0.924,0.383,0,0           # tool orientation, quaternion w,x,y,z (normalised; reported
//                                    # only by a device started with --orientation)
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"
#include "tools/hapsim/device_model.hpp"

namespace kerf::hapsim {

/// Why a hand script was refused.
enum class ScriptErrc : std::uint8_t {
    kUnreadable,  ///< the file cannot be read
    kBadLine,     ///< a line is not a valid action (unknown name, bad number, out of bounds)
};
/// Stable snake_case name ("bad_line").
std::string_view to_string(ScriptErrc code) noexcept;

/// A refused script (kerf::Error): where is "<file>:<line>", or "<file>" when the file itself
/// could not be read (line 0).
struct ScriptError : Error<ScriptErrc> {
    int line = 0;  ///< 1-based line of the bad action; 0 when the file could not be read
};

struct ScriptAction {
    enum class Kind { kMove, kHold, kButton, kSweep, kFault, kOrient } kind = Kind::kHold;
    std::array<double, 4> quaternion{1, 0, 0, 0};  ///< orient: unit (w, x, y, z)
    Vec3 vec{};                                    ///< move: target; sweep: amplitude
    double duration_s = 0;
    double frequency_hz = 0;  ///< sweep
    int button = 0;
    bool pressed = false;
    std::string fault_name, fault_value;
    int line = 0;
};

using HandScript = std::vector<ScriptAction>;

Result<HandScript, ScriptError> parse_hand_script(std::string_view text, std::string_view source);
Result<HandScript, ScriptError> load_hand_script(const std::filesystem::path& path);

/// A fault event fired by the script.
struct FaultEvent {
    std::string name, value;
};

/// Plays a script against time.
class HandPlayer {
public:
    HandPlayer(HandScript script, const Vec3& start_m);
    /// Advances to `t_s` (monotonic); appends fault events fired on the way to `events`.
    void advance(double t_s, std::vector<FaultEvent>& events);

    const Vec3& position_m() const noexcept { return pos_; }
    const Vec3& velocity_m_per_s() const noexcept { return vel_; }
    unsigned buttons() const noexcept { return buttons_; }
    /// The hand's tool orientation, unit quaternion (w, x, y, z); identity until an `orient`.
    const std::array<double, 4>& orientation_wxyz() const noexcept { return orientation_; }
    bool finished() const noexcept { return index_ >= script_.size(); }

private:
    HandScript script_;
    std::size_t index_ = 0;
    double action_start_s_ = 0;
    bool started_ = false;
    Vec3 from_{}, pos_{}, vel_{};
    unsigned buttons_ = 0;
    std::array<double, 4> orientation_{1, 0, 0, 0};
};

}  // namespace kerf::hapsim
