// libFuzzer target: every Kerf HID and Falcon decoder over arbitrary bytes. A decoded report must
// re-encode to bytes that decode to the same value (the codec's round-trip contract).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>

#include "firmware_host/falcon/falcon_packet.hpp"
#include "firmware_host/protocol/kerf_hid_codec.hpp"

namespace fh = kerf::firmware_host;

namespace {

template <class T, class Decode, class Encode>
void round_trip(std::span<const std::byte> in, Decode decode, Encode encode) {
    T value{};
    if (decode(in, value) != fh::CodecStatus::kOk) return;
    std::array<std::byte, fh::kReportSize> out{};
    if (encode(value, out) != fh::CodecStatus::kOk) std::abort();
    if (std::memcmp(out.data(), in.data(), out.size()) != 0) std::abort();  // bit-exact
    T again{};
    if (decode(out, again) != fh::CodecStatus::kOk || !(again == value)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::byte> in(reinterpret_cast<const std::byte*>(data), size);
    round_trip<fh::InputReport>(in, fh::decode_input, fh::encode_input);
    round_trip<fh::OutputReport>(in, fh::decode_output, fh::encode_output);
    round_trip<fh::IdentityReport>(in, fh::decode_identity, fh::encode_identity);
    round_trip<fh::MechanicsReport>(in, fh::decode_mechanics, fh::encode_mechanics);
    round_trip<fh::ConfigReport>(in, fh::decode_config, fh::encode_config);
    fh::falcon::FalconReport rep;
    if (fh::falcon::decode_report(in, rep) == fh::falcon::FalconCodecStatus::kOk) {
        std::array<std::byte, fh::falcon::kPacketSize> out{};
        (void)fh::falcon::encode_report(rep, out);
        if (std::memcmp(out.data(), in.data(), out.size()) != 0) std::abort();
        fh::falcon::FalconReport again;
        if (fh::falcon::decode_report(out, again) != fh::falcon::FalconCodecStatus::kOk ||
            !(again == rep)) {
            std::abort();
        }
    }
    fh::falcon::FalconCommand cmd;
    (void)fh::falcon::decode_command(in, cmd);
    return 0;
}
