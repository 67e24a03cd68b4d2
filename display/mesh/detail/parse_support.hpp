// Internal: what every format parser shares — the parse context, error construction, number
// parsing, and a bounds-checked text scanner that knows its line number.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "config/base/result.hpp"
#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/mesh_error.hpp"

namespace kerf::mesh::detail {

/// Where the bytes came from and how to scale them to metres.
struct ParseContext {
    std::string_view name;
    double metres_per_unit;

    MeshError error(MeshErrc kind, std::size_t line, std::size_t offset, std::string detail) const;
};

/// A token shown in an error message: at most 32 characters, non-printable bytes as '?'.
std::string quote(std::string_view token);

/// Parses a whole token as a decimal floating-point number ("+1.5e3", "nan", "inf" included);
/// a number beyond double's range gives infinity.
std::optional<double> parse_double(std::string_view token) noexcept;

/// Parses a whole token as a signed 64-bit integer.
std::optional<long long> parse_integer(std::string_view token) noexcept;

/// Scales a file coordinate to metres; nullopt when the result is not finite.
std::optional<Point> to_metres(double x, double y, double z, double metres_per_unit) noexcept;

/// Walks text by whitespace-separated tokens or by lines, counting lines from 1.
class TextScanner {
public:
    explicit TextScanner(std::string_view text, std::size_t start = 0) : text_(text), pos_(start) {}

    /// Next token, crossing line breaks; empty at end of input.
    std::string_view next_token();
    /// Next token on the current line only; empty at the end of the line.
    std::string_view next_token_on_line();
    /// The rest of the current line (without the line break), moving to the next line.
    std::string_view rest_of_line();
    /// Next line (without "\r\n" / "\n"), or nullopt at end of input.
    std::optional<std::string_view> next_line();

    bool at_end() const noexcept { return pos_ >= text_.size(); }
    std::size_t line() const noexcept { return line_; }         ///< line of the last token
    std::size_t offset() const noexcept { return token_pos_; }  ///< offset of the last token
    std::size_t position() const noexcept { return pos_; }
    std::size_t remaining() const noexcept { return text_.size() - pos_; }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
    std::size_t cur_line_ = 1;
    std::size_t token_pos_ = 0;
};

/// The bytes as characters.
inline std::string_view as_text(std::span<const std::byte> bytes) noexcept {
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace kerf::mesh::detail
