// Text from outside the process (shared memory, devices, file names) made safe for a terminal:
// every byte outside printable ASCII becomes \xNN, so no escape sequence ever reaches the screen.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace kerf::cli {

/// `text` with every byte outside 0x20..0x7e (and the backslash) written as \xNN.
inline std::string safe_text(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte <= 0x7e && byte != '\\') {
            out += c;
            continue;
        }
        char buf[5];
        std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(byte));
        out += buf;
    }
    return out;
}

/// safe_text() of a fixed-size, maybe unterminated character field.
inline std::string safe_field(const char* field, std::size_t size) {
    std::size_t n = 0;
    while (n < size && field[n] != '\0') ++n;
    return safe_text(std::string_view(field, n));
}

}  // namespace kerf::cli
