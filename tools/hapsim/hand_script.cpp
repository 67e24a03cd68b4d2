#include "tools/hapsim/hand_script.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include "config/file_io/file_io.hpp"
#include "tools/hapsim/faults.hpp"

namespace kerf::hapsim {
namespace {

/// A hand script is text, one action a line: 64 MiB is far more than a day of actions.
constexpr std::uint64_t kMaxScriptBytes = 64u << 20;

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
        s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i) {
        if (i == line.size() || line[i] == ',') {
            out.push_back(trim(line.substr(start, i - start)));
            start = i + 1;
        }
    }
    return out;
}

bool number(std::string_view s, double& out) {
    std::string tmp(s);  // strtod: from_chars for double is fine on gcc 12, but be portable
    char* end = nullptr;
    out = std::strtod(tmp.c_str(), &end);
    return !tmp.empty() && end == tmp.c_str() + tmp.size() && std::isfinite(out);
}

// Parses fields[1..] as numbers; the error says which action wanted what.
bool numbers(const std::vector<std::string_view>& f, std::size_t count, const char* usage,
             double* out, std::string& why) {
    if (f.size() != count + 1) {
        why = std::string(f[0]) + ": expected " + std::to_string(count) + " values (" + usage +
              "), got " + std::to_string(f.size() - 1);
        return false;
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (!number(f[i + 1], out[i])) {
            why = std::string(f[0]) + ": value " + std::to_string(i + 1) + " '" +
                  std::string(f[i + 1]) + "' is not a finite number (" + usage + ")";
            return false;
        }
    }
    return true;
}

bool parse_action(const std::vector<std::string_view>& f, ScriptAction& a, std::string& why) {
    double v[6] = {};
    const auto& name = f[0];
    if (name == "move") {
        if (!numbers(f, 4, "x_m,y_m,z_m,duration_s", v, why)) return false;
        a.kind = ScriptAction::Kind::kMove;
        a.vec = {v[0], v[1], v[2]};
        a.duration_s = v[3];
    } else if (name == "hold") {
        if (!numbers(f, 1, "duration_s", v, why)) return false;
        a.kind = ScriptAction::Kind::kHold;
        a.duration_s = v[0];
    } else if (name == "sweep") {
        if (!numbers(f, 5, "ax_m,ay_m,az_m,frequency_hz,duration_s", v, why)) return false;
        a.kind = ScriptAction::Kind::kSweep;
        a.vec = {v[0], v[1], v[2]};
        a.duration_s = v[4];
        a.frequency_hz = v[3];
        if (v[3] <= 0) return (why = "sweep: frequency_hz must be > 0", false);
    } else if (name == "button") {
        if (f.size() != 3 || !number(f[1], v[0]) || v[0] < 0 || v[0] > 15 ||
            v[0] != std::floor(v[0]) || (f[2] != "down" && f[2] != "up")) {
            return (why = "button: expected index 0..15 and down|up, e.g. button,0,down", false);
        }
        a.kind = ScriptAction::Kind::kButton;
        a.button = static_cast<int>(v[0]);
        a.pressed = f[2] == "down";
    } else if (name == "fault") {
        if (f.size() != 3 || f[1].empty() || f[2].empty()) {
            return (why = "fault: expected a name and on|off|<number>, e.g. fault,drop,on", false);
        }
        Faults scratch;  // the same check the run applies: an unknown name or value fails here
        if (auto bad = apply_fault(scratch, f[1], f[2]); !bad.empty()) return (why = bad, false);
        a.kind = ScriptAction::Kind::kFault;
        a.fault_name = f[1];
        a.fault_value = f[2];
    } else if (name == "orient") {
        if (!numbers(f, 4, "w,x,y,z", v, why)) return false;
        const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
        if (!(n > 1e-6)) return (why = "orient: the quaternion w,x,y,z must not be zero", false);
        a.kind = ScriptAction::Kind::kOrient;
        a.quaternion = {v[0] / n, v[1] / n, v[2] / n, v[3] / n};
    } else {
        why =
            "unknown action '" + std::string(name) + "' (move, hold, button, sweep, fault, orient)";
        return false;
    }
    if (a.duration_s < 0) return (why = std::string(name) + ": duration_s must be >= 0", false);
    return true;
}

ScriptError script_error(ScriptErrc code, std::string_view source, int line, std::string what) {
    ScriptError e;
    e.code = code;
    e.where = std::string(source);
    if (line > 0) e.where += ":" + std::to_string(line);
    e.what = std::move(what);
    e.line = line;
    return e;
}

}  // namespace

std::string_view to_string(ScriptErrc code) noexcept {
    switch (code) {
        case ScriptErrc::kUnreadable:
            return "unreadable";
        case ScriptErrc::kBadLine:
            return "bad_line";
    }
    return "unknown";
}

Result<HandScript, ScriptError> parse_hand_script(std::string_view text, std::string_view source) {
    HandScript script;
    std::istringstream in{std::string(text)};
    std::string raw;
    int line_no = 0;
    while (std::getline(in, raw)) {
        ++line_no;
        std::string_view line = raw;
        if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        line = trim(line);
        if (line.empty()) continue;
        ScriptAction a;
        std::string why;
        if (!parse_action(split(line), a, why))
            return Err{script_error(ScriptErrc::kBadLine, source, line_no, std::move(why))};
        a.line = line_no;
        script.push_back(std::move(a));
    }
    return script;
}

Result<HandScript, ScriptError> load_hand_script(const std::filesystem::path& path) {
    // A regular file only (never a FIFO, a directory or a link to a device), at most the cap.
    auto bytes = files::read_regular_file(path, kMaxScriptBytes);
    if (!bytes) {
        return Err{script_error(ScriptErrc::kUnreadable, path.string(), 0, bytes.error().what)};
    }
    return parse_hand_script(
        std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()),
        path.string());
}

HandPlayer::HandPlayer(HandScript script, const Vec3& start_m)
    : script_(std::move(script)), from_(start_m), pos_(start_m) {}

void HandPlayer::advance(double t_s, std::vector<FaultEvent>& events) {
    vel_ = {};
    while (index_ < script_.size()) {
        const auto& a = script_[index_];
        if (!started_) {  // actions run back to back from t = 0: each starts where the last ended
            from_ = pos_;
            started_ = true;
        }
        if (a.kind == ScriptAction::Kind::kButton || a.kind == ScriptAction::Kind::kFault ||
            a.kind == ScriptAction::Kind::kOrient) {
            if (a.kind == ScriptAction::Kind::kOrient) {
                orientation_ = a.quaternion;
            } else if (a.kind == ScriptAction::Kind::kButton) {
                buttons_ =
                    a.pressed ? (buttons_ | (1U << a.button)) : (buttons_ & ~(1U << a.button));
            } else {
                events.push_back({a.fault_name, a.fault_value});
            }
            ++index_;
            started_ = false;
            continue;
        }
        const double u = a.duration_s > 0 ? (t_s - action_start_s_) / a.duration_s : 1.0;
        const double s = std::min(1.0, std::max(0.0, u));
        const double tau = s * a.duration_s;
        for (int k = 0; k < 3; ++k) {
            if (a.kind == ScriptAction::Kind::kMove) {
                pos_[k] = from_[k] + (a.vec[k] - from_[k]) * s;
                vel_[k] =
                    (u < 1.0 && a.duration_s > 0) ? (a.vec[k] - from_[k]) / a.duration_s : 0.0;
            } else if (a.kind == ScriptAction::Kind::kSweep) {
                const double w = 2 * std::numbers::pi * a.frequency_hz;
                pos_[k] = from_[k] + a.vec[k] * std::sin(w * tau);
                vel_[k] = u < 1.0 ? a.vec[k] * w * std::cos(w * tau) : 0.0;
            }
        }
        if (u < 1.0) return;
        if (a.kind == ScriptAction::Kind::kSweep) pos_ = from_;  // a sweep ends where it began
        action_start_s_ += a.duration_s;
        ++index_;
        started_ = false;
    }
}

}  // namespace kerf::hapsim
