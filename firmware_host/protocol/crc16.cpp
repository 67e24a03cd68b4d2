#include "firmware_host/protocol/crc16.hpp"

#include <array>

namespace kerf::firmware_host {
namespace {

constexpr std::array<std::uint16_t, 256> make_table() {
    std::array<std::uint16_t, 256> table{};
    for (unsigned i = 0; i < 256; ++i) {
        auto crc = static_cast<std::uint16_t>(i << 8);
        for (int bit = 0; bit < 8; ++bit) {
            crc = (crc & 0x8000U) != 0 ? static_cast<std::uint16_t>((crc << 1) ^ 0x1021U)
                                       : static_cast<std::uint16_t>(crc << 1);
        }
        table[i] = crc;
    }
    return table;
}

constexpr std::array<std::uint16_t, 256> kTable = make_table();

}  // namespace

std::uint16_t crc16_ccitt(std::span<const std::byte> bytes) noexcept {
    std::uint16_t crc = 0xFFFF;
    for (std::byte b : bytes) {
        const auto index = static_cast<std::uint8_t>((crc >> 8) ^ std::to_integer<unsigned>(b));
        crc = static_cast<std::uint16_t>((crc << 8) ^ kTable[index]);
    }
    return crc;
}

}  // namespace kerf::firmware_host
