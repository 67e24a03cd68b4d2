// Faults kerf-hapsim can inject, by script (`fault,<name>,<value>`) or by command on stdin
// (`fault <name> <value>`). Names and values:
//   drop on|off            device replies are dropped
//   delay <ms>|off         device replies are held back <ms> of wall time
//   corrupt on|off         one byte of every reply is flipped (bit 7)
//   short on|off           every reply is cut to half its length
//   unplug on|off          the connection is closed; off = replug (accept again)
//   stuck_encoder on|off   reported position frozen (Kerf: the firmware flags an encoder fault)
//   estop on|off           the e-stop is pressed (Kerf protocol)
//   watchdog_trip on       the device-side watchdog trips as if commands had stopped (Kerf)
//   firmware_fail on|off   every firmware chunk is echoed wrong (Falcon): loading fails
//   echo_mismatch <n>      the next n firmware chunks are echoed wrong (Falcon): retries succeed
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace kerf::hapsim {

struct Faults {
    bool drop = false;
    std::uint32_t delay_ms = 0;
    bool corrupt = false;
    bool short_packets = false;
    bool unplugged = false;
    bool stuck_encoder = false;
    bool estop = false;
    bool watchdog_trip = false;  ///< one-shot: the protocol side consumes it
    bool firmware_fail = false;
    int echo_mismatch_left = 0;
};

/// Applies one fault setting; returns an empty string, or why it was refused.
std::string apply_fault(Faults& faults, std::string_view name, std::string_view value);

}  // namespace kerf::hapsim
