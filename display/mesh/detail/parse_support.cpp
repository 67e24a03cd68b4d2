#include "display/mesh/detail/parse_support.hpp"

#include <charconv>
#include <cmath>

namespace kerf::mesh::detail {
namespace {

bool is_space(char c) noexcept {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

}  // namespace

MeshError ParseContext::error(MeshErrc kind, std::size_t line, std::size_t offset,
                              std::string detail) const {
    return mesh_error(kind, name, line, offset, std::move(detail));
}

std::string quote(std::string_view token) {
    std::string out = "'";
    for (std::size_t i = 0; i < token.size() && i < 32; ++i) {
        const unsigned char c = static_cast<unsigned char>(token[i]);
        out += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
    }
    if (token.size() > 32) out += "...";
    return out + "'";
}

std::optional<double> parse_double(std::string_view token) noexcept {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty() || token.front() == '+') return std::nullopt;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    // Beyond double's range (either way): reported by the caller as a non-finite value.
    if (ec == std::errc::result_out_of_range) return HUGE_VAL;
    if (ec != std::errc{} || end != token.data() + token.size()) return std::nullopt;
    return v;
}

std::optional<long long> parse_integer(std::string_view token) noexcept {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    long long v = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (token.empty() || ec != std::errc{} || end != token.data() + token.size()) {
        return std::nullopt;
    }
    return v;
}

std::optional<Point> to_metres(double x, double y, double z, double metres_per_unit) noexcept {
    const Point p{x * metres_per_unit, y * metres_per_unit, z * metres_per_unit};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return std::nullopt;
    return p;
}

std::string_view TextScanner::next_token() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
        if (text_[pos_] == '\n') ++cur_line_;
        ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    line_ = cur_line_;
    token_pos_ = start;
    return text_.substr(start, pos_ - start);
}

std::string_view TextScanner::next_token_on_line() {
    while (pos_ < text_.size() && is_space(text_[pos_]) && text_[pos_] != '\n') ++pos_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    line_ = cur_line_;
    token_pos_ = start;
    return text_.substr(start, pos_ - start);
}

std::string_view TextScanner::rest_of_line() {
    const std::size_t start = pos_;
    const std::size_t nl = text_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
    pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
    line_ = cur_line_;
    token_pos_ = start;
    if (nl != std::string_view::npos) ++cur_line_;
    std::string_view line = text_.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return line;
}

std::optional<std::string_view> TextScanner::next_line() {
    if (at_end()) return std::nullopt;
    return rest_of_line();
}

}  // namespace kerf::mesh::detail
