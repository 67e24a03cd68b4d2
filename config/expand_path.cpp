#include "config/expand_path.hpp"

#include <cstdlib>

namespace kerf::config {
namespace {

std::string env_or_tmp(const char* name) {
    const char* v = std::getenv(name);
    return (v != nullptr && v[0] == '/') ? std::string(v) : std::string("/tmp");
}

/// The value of variable `name`, or false when it is not one of ours.
bool lookup(std::string_view name, const PathVars& vars, std::string* out) {
    if (name == "config")
        *out = vars.config_dir.string();
    else if (name == "shared")
        *out = vars.shared_dir.string();
    else if (name == "tmp")
        *out = env_or_tmp("TMPDIR");
    else if (name == "runtime")
        *out = env_or_tmp("XDG_RUNTIME_DIR");
    else
        return false;
    return true;
}

/// Walks `raw`, calling `var(name)` for each `${name}` and `text(chunk)` for the rest.
/// Returns false (with the offending text in `bad`) on an unterminated or unknown variable.
template <class Text, class Var>
bool scan(std::string_view raw, std::string* bad, Text text, Var var) {
    std::size_t i = 0;
    while (i < raw.size()) {
        std::size_t open = raw.find("${", i);
        if (open == std::string_view::npos) open = raw.size();
        text(raw.substr(i, open - i));
        if (open == raw.size()) break;
        std::size_t close = raw.find('}', open + 2);
        if (close == std::string_view::npos) {
            if (bad) *bad = std::string(raw.substr(open));
            return false;
        }
        std::string_view name = raw.substr(open + 2, close - open - 2);
        if (!var(name)) {
            if (bad) *bad = "${" + std::string(name) + "}";
            return false;
        }
        i = close + 1;
    }
    return true;
}

}  // namespace

bool check_path_template(std::string_view raw, std::string* bad) {
    PathVars none;
    std::string ignored;
    return scan(
        raw, bad, [](std::string_view) {},
        [&](std::string_view name) { return lookup(name, none, &ignored); });
}

Result<std::filesystem::path, ConfigError> expand_path(std::string_view raw, const PathVars& vars) {
    std::string out;
    std::string bad;
    bool ok = scan(
        raw, &bad, [&](std::string_view chunk) { out += chunk; },
        [&](std::string_view name) {
            std::string value;
            if (!lookup(name, vars, &value)) return false;
            out += value;
            return true;
        });
    if (!ok || raw.empty()) {
        ConfigError e;
        e.code = ConfigErrc::kBadReference;
        e.value = "\"" + std::string(raw.substr(0, 60)) + "\"";
        e.expected = "a path; variables ${config}, ${shared}, ${tmp}, ${runtime}";
        e.note = raw.empty() ? "empty path" : "cannot expand " + bad;
        return Err{described(e)};
    }
    std::filesystem::path p(out);
    if (p.is_relative()) p = vars.config_dir / p;
    return p.lexically_normal();
}

}  // namespace kerf::config
