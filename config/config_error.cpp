#include "config/config_error.hpp"

namespace kerf::config {

std::string_view to_string(ConfigErrorKind kind) noexcept {
    switch (kind) {
        case ConfigErrorKind::kIo:
            return "cannot read";
        case ConfigErrorKind::kSyntax:
            return "syntax error";
        case ConfigErrorKind::kUnknownKey:
            return "unknown key";
        case ConfigErrorKind::kMissingKey:
            return "missing key";
        case ConfigErrorKind::kWrongType:
            return "wrong type";
        case ConfigErrorKind::kOutOfRange:
            return "out of range";
        case ConfigErrorKind::kNonFinite:
            return "not finite";
        case ConfigErrorKind::kBadUnit:
            return "bad unit";
        case ConfigErrorKind::kBadValue:
            return "bad value";
        case ConfigErrorKind::kBadReference:
            return "dangling reference";
    }
    return "unknown problem";
}

std::string ConfigError::message() const {
    std::string s = source.empty() ? std::string("<config>") : source;
    if (line != 0) {
        s += ":" + std::to_string(line);
        if (column != 0) s += ":" + std::to_string(column);
    }
    s += ": ";
    if (!key.empty()) {
        s += key;
        if (!value.empty()) s += " = " + value;
        s += ": ";
    }
    s += to_string(kind);
    if (!expected.empty()) s += " (expected " + expected + ")";
    if (!note.empty()) s += (expected.empty() ? ": " : "; ") + note;
    if (more_problems == 1) s += " [and 1 more problem]";
    if (more_problems > 1) s += " [and " + std::to_string(more_problems) + " more problems]";
    return s;
}

}  // namespace kerf::config
