// Loads the Falcon's firmware image (a file the user supplies; Kerf never ships it) through the
// FTDI boot-loader handshake (PROTOCOL.md §6), as an explicit state machine over UsbLink.
// Open-time only: every step is bounded by a timeout, none is real-time.
//
//   auto image = read_firmware_image(path);           // Result<vector<byte>, FirmwareError>
//   if (auto s = load_firmware(link, *image); !s) print(s.error().message());
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"
#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host::falcon {

inline constexpr std::size_t kFirmwareChunkSize = 62;  ///< 64-byte packet minus 2 status bytes
inline constexpr std::size_t kMaxFirmwareImageBytes = 1U << 20;

/// Why a firmware image could not be read or loaded.
enum class FirmwareErrc : std::uint8_t {
    kImageUnreadable,   ///< missing, a directory, or a read failed
    kImageEmpty,        ///< no bytes
    kImageTooLarge,     ///< over kMaxFirmwareImageBytes
    kSetupFailed,       ///< an FTDI control request failed
    kHandshakeFailed,   ///< no `0A 44 2C 0D` answer to `0A 43 0D`
    kProbeFailed,       ///< no `41` answer to `41` at the load baud rate
    kEchoMismatch,      ///< a chunk echoed back different bytes on every attempt
    kEchoTimeout,       ///< a chunk's echo did not arrive in time on every attempt
    kWriteFailed,       ///< a bulk OUT failed
    kNormalModeFailed,  ///< switching to the 1 kHz serial set-up failed
};
/// Stable snake_case name ("echo_mismatch").
std::string_view to_string(FirmwareErrc code) noexcept;

/// A failed read or load (kerf::Error): where is the image path, or "falcon firmware"; what is
/// the sentence with the failing chunk's offset, the transfer status and the attempts made,
/// which are also kept as numbers.
struct FirmwareError : Error<FirmwareErrc> {
    std::size_t offset = 0;             ///< image offset of the failing chunk
    LinkStatus link = LinkStatus::kOk;  ///< the transfer status behind it, if any
    int attempts = 0;                   ///< whole-load attempts made
};

/// Builds a FirmwareError and its where/what text from the parts.
FirmwareError firmware_error(FirmwareErrc code, std::string path = {}, std::size_t offset = 0,
                             LinkStatus link = LinkStatus::kOk, int attempts = 0);

/// Reads and size-checks an image file.
Result<std::vector<std::byte>, FirmwareError> read_firmware_image(const std::filesystem::path& p);

struct FirmwareLoadOptions {
    std::uint32_t transfer_timeout_ms = 1000;  ///< per control request / write / echo
    int handshake_tries = 100;                 ///< `0A 43 0D` attempts per load attempt
    int load_attempts = 3;                     ///< whole loads (firmware mode re-entered each time)
};

/// The state machine. `step()` performs one bounded action and returns the new state.
class FirmwareLoader {
public:
    enum class State : std::uint8_t {
        kFirmwareMode,
        kHandshake,
        kLoadBaud,
        kProbe,
        kChunk,
        kNormalMode,
        kDone,
        kFailed
    };
    FirmwareLoader(UsbLink& link, std::span<const std::byte> image, FirmwareLoadOptions options);

    State step() noexcept;
    State state() const noexcept { return state_; }
    std::size_t bytes_loaded() const noexcept { return offset_; }
    int attempts() const noexcept { return attempt_; }
    FirmwareError error() const;  ///< valid in kFailed

private:
    State fail_attempt(FirmwareErrc code, LinkStatus link) noexcept;
    State fail(FirmwareErrc code, LinkStatus link) noexcept;
    State do_handshake() noexcept;
    State do_probe() noexcept;
    State do_chunk() noexcept;

    UsbLink& link_;
    std::span<const std::byte> image_;
    FirmwareLoadOptions options_;
    State state_ = State::kFirmwareMode;
    std::size_t offset_ = 0;
    int attempt_ = 1;
    FirmwareErrc failed_code_ = FirmwareErrc::kSetupFailed;  ///< valid in kFailed, with:
    LinkStatus failed_link_ = LinkStatus::kOk;
    std::size_t failed_offset_ = 0;
    int failed_attempts_ = 0;
};

/// Runs the state machine to kDone or kFailed.
Status<FirmwareError> load_firmware(UsbLink& link, std::span<const std::byte> image,
                                    const FirmwareLoadOptions& options = {});

/// Reads payload bytes (status bytes stripped) until `want` arrived or `timeout_ms` passed;
/// returns how many arrived. Shared by the loader and the Falcon device's probe.
std::size_t read_payload(UsbLink& link, std::span<std::byte> out, std::size_t want,
                         std::uint32_t timeout_ms, LinkStatus& last) noexcept;

}  // namespace kerf::firmware_host::falcon
