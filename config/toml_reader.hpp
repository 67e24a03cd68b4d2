// Internal to kerf_config (not for other modules): a strict reader over a toml++ table.
//
// Each accessor looks a key up, checks its type, finiteness and range, records a ConfigError
// with the key's file position when something is wrong and returns a fallback so that parsing
// goes on and finds every problem. Every key an accessor asks for is remembered; at the end,
// `Problems::report_unknown_keys()` walks the whole document and reports every other key as
// unknown (with a "did you mean" hint, or kBadUnit when only the unit suffix differs), so no
// table can forget the check. No exceptions escape.
#pragma once

#include <toml++/toml.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "config/base/result.hpp"
#include "config/config_error.hpp"

namespace kerf::config::detail {

/// An accepted numeric interval; open ends are exclusive.
struct Range {
    double min = 0;
    double max = 0;
    bool min_open = false;
    bool max_open = false;
    std::string_view unit;  ///< shown after the range, e.g. "N/m"

    bool contains(double v) const noexcept;
    std::string describe() const;  ///< "0 < value <= 100000 N/m"
};
Range positive(double max, std::string_view unit);            ///< (0, max]
Range non_negative(double max, std::string_view unit);        ///< [0, max]
Range closed(double min, double max, std::string_view unit);  ///< [min, max]

/// The problems found in one source, and the rule for which to report.
class Problems {
public:
    explicit Problems(std::string source) : source_(std::move(source)) {}
    const std::string& source() const noexcept { return source_; }
    bool empty() const noexcept { return list_.empty(); }
    /// Records a problem at `where` (a node's or key's source region).
    void add(ConfigErrc kind, const toml::source_region& where, std::string key, std::string value,
             std::string expected, std::string note = {});
    void add(ConfigError error) { list_.push_back(described(std::move(error))); }
    /// The most useful problem: unknown keys (and unit-suffix mistakes) first, then bad values,
    /// then missing keys; document order within each.
    /// @pre !empty()
    ConfigError first() const;
    /// Remembers that the schema knows `key` in `table`.
    void mark_known(const toml::table* table, std::string_view key);
    /// Reports every key, in every table read through a TableReader, that no accessor asked for.
    void report_unknown_keys(const toml::table& root);

private:
    void walk(const toml::table& table, const std::string& path);
    void report_unknown(const toml::key& key, const std::string& full,
                        const std::string& table_path, const std::vector<std::string>& known);

    std::string source_;
    std::vector<ConfigError> list_;
    std::vector<std::pair<const toml::table*, std::vector<std::string>>> known_;
};

/// Strict typed access to one TOML table; `path` is its dotted key path ("" for the root).
class TableReader {
public:
    TableReader(const toml::table& table, std::string path, Problems& problems);

    bool has(std::string_view key) const;
    double number(std::string_view key, const Range& range);
    double number_or(std::string_view key, double fallback, const Range& range);
    std::int64_t integer(std::string_view key, std::int64_t min, std::int64_t max);
    std::int64_t integer_or(std::string_view key, std::int64_t fallback, std::int64_t min,
                            std::int64_t max);
    bool boolean_or(std::string_view key, bool fallback);
    std::string string(std::string_view key);
    std::string string_or(std::string_view key, std::string fallback);
    /// A string that must be one of `names`; returns its index (0 on error).
    std::size_t choice(std::string_view key, const std::vector<std::string_view>& names,
                       ConfigErrc bad_kind = ConfigErrc::kBadValue);
    std::size_t choice_or(std::string_view key, std::size_t fallback,
                          const std::vector<std::string_view>& names);
    /// A list of exactly N numbers, each in `range`.
    template <std::size_t N>
    std::array<double, N> numbers(std::string_view key, const Range& range);
    std::vector<std::int64_t> integer_list_or(std::string_view key, std::int64_t min,
                                              std::int64_t max, std::size_t max_len);
    /// A sub-table; when absent and `required`, records kMissingKey and reads an empty table.
    TableReader table(std::string_view key, bool required = true);
    /// An array of tables (`[[key]]`); when absent records kMissingKey.
    std::vector<TableReader> tables(std::string_view key);
    /// Accepts `key` as known but records kBadValue with `why` when it is present.
    void forbid(std::string_view key, std::string why);
    /// Records a problem about `key` of this table (its value's position, or the table's).
    void fail(std::string_view key, ConfigErrc kind, std::string expected, std::string note = {});
    std::string key_path(std::string_view key) const;
    const toml::table& raw() const noexcept { return *table_; }
    Problems& problems() noexcept { return *problems_; }

private:
    const toml::node* lookup(std::string_view key, std::string_view expected);
    void wrong_type(std::string_view key, const toml::node& node, std::string_view expected);
    void numbers_into(std::string_view key, const Range& range, double* out, std::size_t n);

    const toml::table* table_;
    std::string path_;
    Problems* problems_;
    bool stand_in_ = false;  ///< reading an empty stand-in for a missing table: no missing keys
};

template <std::size_t N>
std::array<double, N> TableReader::numbers(std::string_view key, const Range& range) {
    std::array<double, N> out{};
    numbers_into(key, range, out.data(), N);
    return out;
}

/// A number as short text ("%.10g"): 8.9, 1e-05, 100000.
std::string format_number(double v);

/// TOML text of a node for messages, at most ~60 characters.
std::string describe_value(const toml::node& node);

/// Parses `text` and runs `read(TableReader&)` on the root; returns the first problem if any.
/// `read` returns the value; exceptions from toml++ are caught here.
template <class T, class Read>
Result<T, ConfigError> parse_document(std::string_view text, std::string_view source, Read read);

/// Reads a whole file into a string; kIo error naming the path on failure.
Result<std::string, ConfigError> read_text_file(const std::string& path);

/// True when `name` is a valid profile or session name: 1..64 of [A-Za-z0-9_-].
bool is_plain_name(std::string_view name) noexcept;

/// Parses with toml++; returns the table or a kSyntax error.
Result<toml::table, ConfigError> parse_toml(std::string_view text, std::string_view source);

template <class T, class Read>
Result<T, ConfigError> parse_document(std::string_view text, std::string_view source, Read read) {
    auto doc = parse_toml(text, source);
    if (!doc) return Err{doc.error()};
    Problems problems{std::string(source)};
    TableReader root(*doc, "", problems);
    T value = read(root);
    problems.report_unknown_keys(*doc);
    if (!problems.empty()) {
        ConfigError first = problems.first();
        if (doc->empty())  // say why everything is missing
            first.note = "the file holds no settings (empty, or only comments)";
        return Err{described(std::move(first))};
    }
    return value;
}

}  // namespace kerf::config::detail
