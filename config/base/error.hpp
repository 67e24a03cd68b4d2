// kerf::Error<Code> — the one shape of a failure in Kerf: a code a program branches on, where the
// problem is and what is wrong, printed one way everywhere.
//
//   enum class IpcErrc { kNotFound, kBadHeader };                 // the module's codes
//   std::string_view to_string(IpcErrc c) noexcept;               // "not_found", "bad_header"
//   using IpcError = Error<IpcErrc>;
//
//   return Err{IpcError{IpcErrc::kBadHeader, "segment /kerf.demo", "layout version 3, expected
//   1"}};
//   ...
//   log(r.error().message());  // "segment /kerf.demo: layout version 3, expected 1 (bad_header)"
//
// Rules every module follows:
//   - the code is an `enum class` in the module's namespace with a `to_string(Code) noexcept ->
//     std::string_view` beside it (found by ADL) giving a stable snake_case name;
//   - `where` names the file (with `:line` or `: byte N`), path, segment, device or key;
//   - `what` says what is wrong with the offending value and, where it helps, what is accepted;
//   - printing is `message()` (or format_error() for the same three parts); nothing else formats
//     an error. A module whose callers need machine-readable location parts (a line, a byte
//     offset, a key) derives from Error<Code> and adds them; `where`/`what` still carry the text.
#pragma once

#include <concepts>
#include <string>
#include <string_view>
#include <type_traits>

namespace kerf {

/// An error code: an enum with a noexcept `to_string(Code)` returning std::string_view.
template <class Code>
concept ErrorCode = std::is_enum_v<Code> && requires(Code c) {
    { to_string(c) }
    noexcept->std::same_as<std::string_view>;
};

/// "<where>: <what> (<code_name>)"; the where part and its ": " are left out when `where` is
/// empty, and ": <what>" when `what` is empty.
inline std::string format_error(std::string_view where, std::string_view what,
                                std::string_view code_name) {
    std::string s;
    s.reserve(where.size() + what.size() + code_name.size() + 5);
    s += where;
    if (!where.empty() && !what.empty()) s += ": ";
    s += what;
    if (!s.empty()) s += ' ';
    s += '(';
    s += code_name;
    s += ')';
    return s;
}

/// A failure: its code, where it happened and what is wrong.
template <class Code>
struct Error {
    Code code{};        ///< what kind of failure, for a program to branch on
    std::string where;  ///< the file(:line), path, segment, device or key the problem is in
    std::string what;   ///< what is wrong, with the offending value

    /// The one printed form: format_error(where, what, to_string(code)).
    std::string message() const requires ErrorCode<Code> {
        return format_error(where, what, to_string(code));
    }
};

}  // namespace kerf
