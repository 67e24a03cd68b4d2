// CRC-16/CCITT-FALSE (polynomial 0x1021, initial value 0xFFFF, no reflection, no final XOR),
// the checksum every Kerf HID report carries in its last two bytes (PROTOCOL.md §2).
// Check value: crc16_ccitt("123456789") == 0x29B1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace kerf::firmware_host {

/// CRC-16/CCITT-FALSE of `bytes`. Pure, noexcept, no allocation; table-driven.
std::uint16_t crc16_ccitt(std::span<const std::byte> bytes) noexcept;

}  // namespace kerf::firmware_host
