// Tag bytes that start every datagram on the emulator socket (PROTOCOL.md §7).
#pragma once

#include <cstddef>

namespace kerf::firmware_host::tag {

inline constexpr std::byte kOut{'O'};         ///< host -> device: output report / bulk OUT
inline constexpr std::byte kIn{'I'};          ///< device -> host: input report / bulk IN
inline constexpr std::byte kGetFeature{'G'};  ///< host -> device: u8 report id
inline constexpr std::byte kFeature{'g'};     ///< device -> host: 64-byte feature report, or none
inline constexpr std::byte kSetFeature{'S'};  ///< host -> device: 64-byte feature report
inline constexpr std::byte kSetReply{'s'};    ///< device -> host: u8 1 accepted / 0 refused
inline constexpr std::byte kControl{
    'C'};  ///< host -> device: u8 type, u8 request, u16 value, u16 index
inline constexpr std::byte kControlReply{'c'};  ///< device -> host: u8 1 ok / 0 stall

}  // namespace kerf::firmware_host::tag
