// kerf::config::ConfigError — what went wrong in a configuration file, and exactly where.
//
// Every loader in kerf_config returns `kerf::Result<T, ConfigError>`. An error names the file,
// the line and column, the dotted key path (`cutting.cortical.feed_resistance_n_s_per_m`), the
// offending value as written, and what would have been accepted:
//
//   config/force/default.toml:12:1: contact.stiffness_n_per_m = -800.0: out of range
//       (expected 0 < value <= 100000 N/m) (out_of_range)
//
// When a file has several problems the loader reports the most useful one (a misspelt key
// before the "missing key" it causes, then document order) and counts the rest.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "config/base/error.hpp"

namespace kerf::config {

/// The kind of a configuration problem; each kind has a test.
enum class ConfigErrc : std::uint8_t {
    kIo,            ///< the file could not be read
    kSyntax,        ///< not valid TOML
    kUnknownKey,    ///< a key the schema does not know (typos are never ignored)
    kMissingKey,    ///< a required key is absent
    kWrongType,     ///< e.g. a string where a number is expected
    kOutOfRange,    ///< a number or list length outside its accepted range
    kNonFinite,     ///< inf or nan where a finite number is required
    kBadUnit,       ///< a unit the key does not accept (`units = "furlong"`, `..._n_per_mm`)
    kBadValue,      ///< a string not among the accepted choices, or an invalid combination
    kBadReference,  ///< a named profile or file that does not exist
};

/// Stable snake_case name of the kind, e.g. "unknown_key".
std::string_view to_string(ConfigErrc code) noexcept;

/// The kind in words for a sentence, e.g. "unknown key".
std::string_view describe(ConfigErrc code) noexcept;

/// One configuration problem (kerf::Error) with its location kept as parts for programs:
/// where is `<source>:<line>:<column>` and what is `<key> = <value>: <kind in words> (expected
/// ...); <note> [and N more problems]`, both made from the parts by described().
struct ConfigError : Error<ConfigErrc> {
    std::string source;             ///< file path, or the source name given to a parse_* function
    std::uint32_t line = 0;         ///< 1-based; 0 when not tied to a line (I/O, validator output)
    std::uint32_t column = 0;       ///< 1-based; 0 when unknown
    std::string key;                ///< dotted key path, e.g. "limits.peak_force_n"; may be empty
    std::string value;              ///< the offending value as TOML text (truncated); may be empty
    std::string expected;           ///< what is accepted: a range, a type, a list of choices
    std::string note;               ///< extra detail: "did you mean ...", the TOML parser's words
    std::size_t more_problems = 0;  ///< how many further problems the same file has
};

/// `e` with where and what made from its parts; every change of a part is followed by it.
ConfigError described(ConfigError e);

}  // namespace kerf::config
