#include "config/config_error.hpp"

namespace kerf::config {

std::string_view to_string(ConfigErrc code) noexcept {
    switch (code) {
        case ConfigErrc::kIo:
            return "io";
        case ConfigErrc::kSyntax:
            return "syntax";
        case ConfigErrc::kUnknownKey:
            return "unknown_key";
        case ConfigErrc::kMissingKey:
            return "missing_key";
        case ConfigErrc::kWrongType:
            return "wrong_type";
        case ConfigErrc::kOutOfRange:
            return "out_of_range";
        case ConfigErrc::kNonFinite:
            return "non_finite";
        case ConfigErrc::kBadUnit:
            return "bad_unit";
        case ConfigErrc::kBadValue:
            return "bad_value";
        case ConfigErrc::kBadReference:
            return "bad_reference";
    }
    return "unknown";
}

std::string_view describe(ConfigErrc code) noexcept {
    switch (code) {
        case ConfigErrc::kIo:
            return "cannot read";
        case ConfigErrc::kSyntax:
            return "syntax error";
        case ConfigErrc::kUnknownKey:
            return "unknown key";
        case ConfigErrc::kMissingKey:
            return "missing key";
        case ConfigErrc::kWrongType:
            return "wrong type";
        case ConfigErrc::kOutOfRange:
            return "out of range";
        case ConfigErrc::kNonFinite:
            return "not finite";
        case ConfigErrc::kBadUnit:
            return "bad unit";
        case ConfigErrc::kBadValue:
            return "bad value";
        case ConfigErrc::kBadReference:
            return "dangling reference";
    }
    return "unknown problem";
}

ConfigError described(ConfigError e) {
    e.where = e.source.empty() ? std::string("<config>") : e.source;
    if (e.line != 0) {
        e.where += ":" + std::to_string(e.line);
        if (e.column != 0) e.where += ":" + std::to_string(e.column);
    }
    e.what.clear();
    if (!e.key.empty()) {
        e.what += e.key;
        if (!e.value.empty()) e.what += " = " + e.value;
        e.what += ": ";
    }
    e.what += describe(e.code);
    if (!e.expected.empty()) e.what += " (expected " + e.expected + ")";
    if (!e.note.empty()) e.what += (e.expected.empty() ? ": " : "; ") + e.note;
    if (e.more_problems == 1) e.what += " [and 1 more problem]";
    if (e.more_problems > 1) {
        e.what += " [and " + std::to_string(e.more_problems) + " more problems]";
    }
    return e;
}

}  // namespace kerf::config
