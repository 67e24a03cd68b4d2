#include "config/toml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <system_error>

#include "config/file_io/file_io.hpp"

namespace kerf::config::detail {
namespace {

constexpr std::size_t kMaxValueChars = 60;
constexpr std::uint64_t kMaxFileBytes = 4u << 20;  // a config file is a few kilobytes

std::string truncate(std::string s) {
    if (s.size() > kMaxValueChars) {
        s.resize(kMaxValueChars - 3);
        s += "...";
    }
    return s;
}

std::string quote(std::string_view s) {
    std::string out = "\"";
    for (char c : s) {
        auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", u);
            out += buf;
        } else {
            out += c;
        }
        if (out.size() > kMaxValueChars) break;
    }
    return out + "\"";
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            std::size_t up = row[j];
            std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + cost});
            diag = up;
        }
    }
    return row[b.size()];
}

std::vector<std::string_view> split_tokens(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    while (start <= s.size()) {
        std::size_t end = s.find('_', start);
        if (end == std::string_view::npos) end = s.size();
        out.push_back(s.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

bool is_unit_token(std::string_view t) {
    static constexpr std::string_view kTokens[] = {
        "m",  "mm", "cm",  "um",  "km",  "in",  "ft",  "n",   "kn",      "lbf", "s",  "ms",
        "us", "ns", "per", "deg", "rad", "hz",  "khz", "rpm", "cpm",     "kg",  "g",  "a",
        "v",  "w",  "px",  "mn",  "nm",  "sec", "min", "pct", "percent", "mps", "kb", "mb"};
    return std::find(std::begin(kTokens), std::end(kTokens), t) != std::end(kTokens);
}

/// True when `unknown` and `known` name the same quantity in different units (or `unknown`
/// has no unit at all): `stiffness_n_per_mm` / `stiffness` vs `stiffness_n_per_m`.
bool differs_only_in_unit(std::string_view unknown, std::string_view known) {
    auto u = split_tokens(unknown);
    auto k = split_tokens(known);
    std::size_t common = 0;
    while (common < u.size() && common < k.size() && u[common] == k[common]) ++common;
    if (common == 0 || common == k.size()) return false;
    auto all_units = [](const std::vector<std::string_view>& v, std::size_t from) {
        for (std::size_t i = from; i < v.size(); ++i)
            if (!is_unit_token(v[i])) return false;
        return true;
    };
    return all_units(u, common) && all_units(k, common);
}

}  // namespace

std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

// ---- Range --------------------------------------------------------------------------------

bool Range::contains(double v) const noexcept {
    bool lo = min_open ? v > min : v >= min;
    bool hi = max_open ? v < max : v <= max;
    return lo && hi;
}

std::string Range::describe() const {
    std::string s = format_number(min) + (min_open ? " < value " : " <= value ") +
                    (max_open ? "< " : "<= ") + format_number(max);
    if (!unit.empty()) s += " " + std::string(unit);
    return s;
}

Range positive(double max, std::string_view unit) { return {0.0, max, true, false, unit}; }
Range non_negative(double max, std::string_view unit) { return {0.0, max, false, false, unit}; }
Range closed(double min, double max, std::string_view unit) {
    return {min, max, false, false, unit};
}

// ---- Problems -----------------------------------------------------------------------------

void Problems::add(ConfigErrc kind, const toml::source_region& where, std::string key,
                   std::string value, std::string expected, std::string note) {
    ConfigError e;
    e.code = kind;
    e.source = source_;
    e.line = where.begin.line;
    e.column = where.begin.column;
    e.key = std::move(key);
    e.value = std::move(value);
    e.expected = std::move(expected);
    e.note = std::move(note);
    list_.push_back(described(std::move(e)));
}

ConfigError Problems::first() const {
    auto earlier = [](const ConfigError& a, const ConfigError& b) {
        if ((a.line == 0) != (b.line == 0)) return a.line != 0;
        return a.line != b.line ? a.line < b.line : a.column < b.column;
    };
    // A misspelt key explains the "missing key" it causes; a value problem is more specific
    // than a missing key. Within a rank, document order.
    auto rank = [](const ConfigError& e) {
        if (e.code == ConfigErrc::kUnknownKey) return 0;
        if (e.code == ConfigErrc::kBadUnit && e.value.empty()) return 0;
        return e.code == ConfigErrc::kMissingKey ? 2 : 1;
    };
    const ConfigError* best = nullptr;
    for (const auto& e : list_) {
        if (best == nullptr) {
            best = &e;
            continue;
        }
        int re = rank(e), rb = rank(*best);
        if (re != rb ? re < rb : earlier(e, *best)) best = &e;
    }
    ConfigError out = *best;
    out.more_problems = list_.size() - 1;
    return described(std::move(out));
}

void Problems::mark_known(const toml::table* table, std::string_view key) {
    for (auto& [t, keys] : known_) {
        if (t == table) {
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.emplace_back(key);
            return;
        }
    }
    known_.push_back({table, {}});
    if (!key.empty()) known_.back().second.emplace_back(key);
}

void Problems::report_unknown_keys(const toml::table& root) { walk(root, ""); }

void Problems::report_unknown(const toml::key& key, const std::string& full,
                              const std::string& table_path,
                              const std::vector<std::string>& known) {
    std::string name(key.str());
    std::string hint;
    ConfigErrc kind = ConfigErrc::kUnknownKey;
    std::size_t best = 4;
    for (const auto& k : known) {
        if (differs_only_in_unit(name, k)) {
            kind = ConfigErrc::kBadUnit;
            hint = "units are fixed in the key name: write '" + k + "' (SI)";
            break;
        }
        std::size_t d = edit_distance(name, k);
        if (d < best && d <= std::max<std::size_t>(1, k.size() / 3)) {
            best = d;
            hint = "did you mean '" + k + "'?";
        }
    }
    std::string expected =
        table_path.empty() ? "a top-level key:" : "a key of [" + table_path + "]:";
    for (std::size_t i = 0; i < known.size(); ++i) expected += (i ? ", " : " ") + known[i];
    if (known.empty()) expected = "no keys here";
    add(kind, key.source(), full, "", expected, hint);
}

void Problems::walk(const toml::table& table, const std::string& path) {
    auto it = std::find_if(known_.begin(), known_.end(),
                           [&](const auto& entry) { return entry.first == &table; });
    if (it == known_.end()) return;  // never read as a table: its type error is reported
    const std::vector<std::string>& keys = it->second;
    for (const auto& [k, node] : table) {
        std::string key(k.str());
        std::string full = path.empty() ? key : path + "." + key;
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
            report_unknown(k, full, path, keys);
        } else if (const auto* sub = node.as_table()) {
            walk(*sub, full);
        } else if (const auto* arr = node.as_array()) {
            for (std::size_t i = 0; i < arr->size(); ++i)
                if (const auto* t = arr->get(i)->as_table())
                    walk(*t, full + "[" + std::to_string(i) + "]");
        }
    }
}

// ---- values -------------------------------------------------------------------------------

std::string describe_value(const toml::node& node) {
    if (const auto* s = node.as_string()) return truncate(quote(s->get()));
    if (const auto* i = node.as_integer()) return std::to_string(i->get());
    if (const auto* f = node.as_floating_point()) {
        double v = f->get();
        if (std::isnan(v)) return "nan";
        if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
        return format_number(v);
    }
    if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* a = node.as_array()) {
        std::string s = "[";
        for (std::size_t i = 0; i < a->size() && s.size() < kMaxValueChars; ++i)
            s += (i ? ", " : "") + describe_value(*a->get(i));
        return truncate(s + "]");
    }
    if (node.is_table()) return "{...}";
    std::ostringstream os;
    node.visit([&](const auto& n) { os << n; });
    return truncate(os.str());
}

Result<std::string, ConfigError> read_text_file(const std::string& path) {
    // The one reading rule of every Kerf program (kerf_file_io): a regular file only (never a
    // FIFO, a directory or /dev/zero behind a link; opening never blocks), at most the cap.
    auto bytes = files::read_regular_file(path, kMaxFileBytes);
    if (!bytes) {
        ConfigError e;
        e.code = ConfigErrc::kIo;
        e.source = path;
        e.note = bytes.error().what;
        return Err{described(e)};
    }
    return std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size());
}

bool is_plain_name(std::string_view name) noexcept {
    if (name.empty() || name.size() > 64) return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
    });
}

Result<toml::table, ConfigError> parse_toml(std::string_view text, std::string_view source) {
    ConfigError e;
    e.code = ConfigErrc::kSyntax;
    e.source = std::string(source);
    try {
        return toml::parse(text, std::string(source));
    } catch (const toml::parse_error& err) {
        e.line = err.source().begin.line;
        e.column = err.source().begin.column;
        e.note = std::string(err.description());
    } catch (const std::exception& err) {
        e.note = err.what();
    }
    return Err{described(e)};
}

}  // namespace kerf::config::detail
