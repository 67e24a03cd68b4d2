// Issue 9, item 7: the printing path of every string read from shared memory or a device
// (safe_text / safe_field) never lets a control byte or an escape sequence reach the terminal.
#include "tools/kerf/safe_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace kerf::cli {
namespace {

bool printable_ascii_only(const std::string& s) {
    for (const char c : s) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
            return false;
    }
    return true;
}

TEST(SafeText, EveryControlAndNonAsciiByteBecomesAVisibleEscape) {
    // A serial number as a hostile device would send it: clear the screen, retitle the window
    // (OSC ... BEL), move the cursor, a DEL, a NUL inside, and UTF-8 bytes.
    const std::string hostile = std::string("SN\x1b[2J\x1b]0;pwned\x07\x1b[1;1H\x7f") +
                                std::string(1, '\0') + "\xc3\xa9" + "\\";
    const std::string shown = safe_text(hostile);
    EXPECT_TRUE(printable_ascii_only(shown)) << shown;
    EXPECT_EQ(shown, "SN\\x1b[2J\\x1b]0;pwned\\x07\\x1b[1;1H\\x7f\\x00\\xc3\\xa9\\x5c");
    // Every byte value: nothing outside 0x20..0x7e survives.
    std::string all;
    for (int b = 0; b < 256; ++b) all.push_back(static_cast<char>(b));
    EXPECT_TRUE(printable_ascii_only(safe_text(all)));
}

TEST(SafeText, AFixedFieldStopsAtItsSizeEvenWithoutATerminator) {
    const char field[8] = {'A', '\x1b', 'c', 'B', 'C', 'D', 'E', 'F'};  // no NUL
    EXPECT_EQ(safe_field(field, sizeof field), "A\\x1bcBCDEF");
    const char shorter[8] = {'o', 'k', '\0', '\x1b', 'x', 'x', 'x', 'x'};
    EXPECT_EQ(safe_field(shorter, sizeof shorter), "ok");
}

}  // namespace
}  // namespace kerf::cli
