// TableReader: strict typed access to one TOML table (declared in config/toml_reader.hpp).
#include <cmath>

#include "config/toml_reader.hpp"

namespace kerf::config::detail {
namespace {

std::string_view node_type_name(const toml::node& n) {
    if (n.is_table()) return "a table";
    if (n.is_array()) return "an array";
    if (n.is_string()) return "a string";
    if (n.is_integer()) return "an integer";
    if (n.is_floating_point()) return "a float";
    if (n.is_boolean()) return "a boolean";
    return "a date or time";
}

std::string choices(const std::vector<std::string_view>& names) {
    std::string s = "one of";
    for (std::size_t i = 0; i < names.size(); ++i)
        s += (i ? ", \"" : " \"") + std::string(names[i]) + "\"";
    return s;
}

const toml::table& empty_table() {
    static const toml::table kEmpty;
    return kEmpty;
}

}  // namespace

TableReader::TableReader(const toml::table& table, std::string path, Problems& problems)
    : table_(&table), path_(std::move(path)), problems_(&problems) {
    problems_->mark_known(table_, "");
}

bool TableReader::has(std::string_view key) const { return table_->contains(key); }

std::string TableReader::key_path(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

const toml::node* TableReader::lookup(std::string_view key, std::string_view expected) {
    problems_->mark_known(table_, key);
    const toml::node* n = table_->get(key);
    if (n == nullptr && !expected.empty() && !stand_in_) {
        problems_->add(ConfigErrc::kMissingKey, table_->source(), key_path(key), "",
                       std::string(expected), "required key is missing");
    }
    return n;
}

void TableReader::wrong_type(std::string_view key, const toml::node& node,
                             std::string_view expected) {
    problems_->add(ConfigErrc::kWrongType, node.source(), key_path(key), describe_value(node),
                   std::string(expected), "got " + std::string(node_type_name(node)));
}

void TableReader::fail(std::string_view key, ConfigErrc kind, std::string expected,
                       std::string note) {
    const toml::node* n = table_->get(key);
    problems_->add(kind, n ? n->source() : table_->source(), key_path(key),
                   n ? describe_value(*n) : "", std::move(expected), std::move(note));
}

void TableReader::forbid(std::string_view key, std::string why) {
    if (lookup(key, "") != nullptr) fail(key, ConfigErrc::kBadValue, "", std::move(why));
}

double TableReader::number_or(std::string_view key, double fallback, const Range& range) {
    const toml::node* n = lookup(key, "");
    if (n == nullptr) return fallback;
    if (!n->is_number()) {
        wrong_type(key, *n, "a number, " + range.describe());
        return fallback;
    }
    double v = n->value<double>().value_or(fallback);
    if (!std::isfinite(v)) {
        fail(key, ConfigErrc::kNonFinite, "a finite number, " + range.describe());
        return fallback;
    }
    if (!range.contains(v)) {
        fail(key, ConfigErrc::kOutOfRange, range.describe());
        return fallback;
    }
    return v;
}

double TableReader::number(std::string_view key, const Range& range) {
    if (lookup(key, "a number, " + range.describe()) == nullptr) return range.min;
    return number_or(key, range.min, range);
}

std::int64_t TableReader::integer_or(std::string_view key, std::int64_t fallback, std::int64_t min,
                                     std::int64_t max) {
    const toml::node* n = lookup(key, "");
    if (n == nullptr) return fallback;
    std::string range = std::to_string(min) + " <= value <= " + std::to_string(max);
    if (!n->is_integer()) {
        wrong_type(key, *n, "an integer, " + range);
        return fallback;
    }
    std::int64_t v = n->as_integer()->get();
    if (v < min || v > max) {
        fail(key, ConfigErrc::kOutOfRange, "an integer, " + range);
        return fallback;
    }
    return v;
}

std::int64_t TableReader::integer(std::string_view key, std::int64_t min, std::int64_t max) {
    std::string range = std::to_string(min) + " <= value <= " + std::to_string(max);
    if (lookup(key, "an integer, " + range) == nullptr) return min;
    return integer_or(key, min, min, max);
}

bool TableReader::boolean_or(std::string_view key, bool fallback) {
    const toml::node* n = lookup(key, "");
    if (n == nullptr) return fallback;
    if (!n->is_boolean()) {
        wrong_type(key, *n, "true or false");
        return fallback;
    }
    return n->as_boolean()->get();
}

std::string TableReader::string_or(std::string_view key, std::string fallback) {
    const toml::node* n = lookup(key, "");
    if (n == nullptr) return fallback;
    if (!n->is_string()) {
        wrong_type(key, *n, "a string");
        return fallback;
    }
    return n->as_string()->get();
}

std::string TableReader::string(std::string_view key) {
    if (lookup(key, "a string") == nullptr) return {};
    return string_or(key, {});
}

std::size_t TableReader::choice_or(std::string_view key, std::size_t fallback,
                                   const std::vector<std::string_view>& names) {
    if (!has(key)) {
        problems_->mark_known(table_, key);
        return fallback;
    }
    return choice(key, names);
}

std::size_t TableReader::choice(std::string_view key, const std::vector<std::string_view>& names,
                                ConfigErrc bad_kind) {
    const toml::node* n = lookup(key, choices(names));
    if (n == nullptr) return 0;
    if (!n->is_string()) {
        wrong_type(key, *n, "a string, " + choices(names));
        return 0;
    }
    const std::string& v = n->as_string()->get();
    for (std::size_t i = 0; i < names.size(); ++i)
        if (v == names[i]) return i;
    std::string note;
    for (auto name : names) {
        if (name.size() >= 2 &&
            (v.find(name) != std::string::npos || name.find(v) != std::string::npos)) {
            note = "did you mean \"" + std::string(name) + "\"?";
            break;
        }
    }
    fail(key, bad_kind, choices(names), note);
    return 0;
}

void TableReader::numbers_into(std::string_view key, const Range& range, double* out,
                               std::size_t n) {
    std::string expected = "a list of " + std::to_string(n) + " numbers, each " + range.describe();
    const toml::node* node = lookup(key, expected);
    if (node == nullptr) return;
    const toml::array* arr = node->as_array();
    if (arr == nullptr) {
        wrong_type(key, *node, expected);
        return;
    }
    if (arr->size() != n) {
        fail(key, ConfigErrc::kOutOfRange, expected,
             "has " + std::to_string(arr->size()) + " elements");
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const toml::node& e = *arr->get(i);
        std::string element = key_path(key) + "[" + std::to_string(i) + "]";
        if (!e.is_number()) {
            problems_->add(ConfigErrc::kWrongType, e.source(), element, describe_value(e),
                           "a number, " + range.describe(),
                           "got " + std::string(node_type_name(e)));
            continue;
        }
        double v = e.value<double>().value_or(0.0);
        if (!std::isfinite(v)) {
            problems_->add(ConfigErrc::kNonFinite, e.source(), element, describe_value(e),
                           "a finite number, " + range.describe());
        } else if (!range.contains(v)) {
            problems_->add(ConfigErrc::kOutOfRange, e.source(), element, describe_value(e),
                           range.describe());
        } else {
            out[i] = v;
        }
    }
}

std::vector<std::int64_t> TableReader::integer_list_or(std::string_view key, std::int64_t min,
                                                       std::int64_t max, std::size_t max_len) {
    std::vector<std::int64_t> out;
    const toml::node* node = lookup(key, "");
    if (node == nullptr) return out;
    std::string each = std::to_string(min) + " <= value <= " + std::to_string(max);
    std::string expected = "a list of at most " + std::to_string(max_len) + " integers, " + each;
    const toml::array* arr = node->as_array();
    if (arr == nullptr) {
        wrong_type(key, *node, expected);
        return out;
    }
    if (arr->size() > max_len) {
        fail(key, ConfigErrc::kOutOfRange, expected,
             "has " + std::to_string(arr->size()) + " elements");
        return out;
    }
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const toml::node& e = *arr->get(i);
        std::string element = key_path(key) + "[" + std::to_string(i) + "]";
        if (!e.is_integer()) {
            problems_->add(ConfigErrc::kWrongType, e.source(), element, describe_value(e),
                           "an integer, " + each, "got " + std::string(node_type_name(e)));
        } else if (auto v = e.as_integer()->get(); v < min || v > max) {
            problems_->add(ConfigErrc::kOutOfRange, e.source(), element, describe_value(e), each);
        } else {
            out.push_back(v);
        }
    }
    return out;
}

TableReader TableReader::table(std::string_view key, bool required) {
    const toml::node* n = lookup(key, required ? "a table ([" + key_path(key) + "])" : "");
    if (n != nullptr && n->is_table())
        return TableReader(*n->as_table(), key_path(key), *problems_);
    if (n != nullptr) wrong_type(key, *n, "a table ([" + key_path(key) + "])");
    TableReader stand_in(empty_table(), key_path(key), *problems_);
    // A missing required table is one problem, not one per key; an optional one uses defaults.
    stand_in.stand_in_ = required || n != nullptr || stand_in_;
    return stand_in;
}

std::vector<TableReader> TableReader::tables(std::string_view key) {
    std::vector<TableReader> out;
    std::string expected = "an array of tables ([[" + key_path(key) + "]])";
    const toml::node* n = lookup(key, expected);
    if (n == nullptr) return out;
    const toml::array* arr = n->as_array();
    if (arr == nullptr) {
        wrong_type(key, *n, expected);
        return out;
    }
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const toml::node& e = *arr->get(i);
        std::string path = key_path(key) + "[" + std::to_string(i) + "]";
        if (const toml::table* t = e.as_table()) {
            out.emplace_back(*t, path, *problems_);
        } else {
            problems_->add(ConfigErrc::kWrongType, e.source(), path, describe_value(e), "a table",
                           "got " + std::string(node_type_name(e)));
        }
    }
    return out;
}

}  // namespace kerf::config::detail
