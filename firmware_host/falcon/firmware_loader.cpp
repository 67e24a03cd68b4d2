#include "firmware_host/falcon/firmware_loader.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>

#include "config/file_io/file_io.hpp"
#include "firmware_host/falcon/ftdi.hpp"

namespace kerf::firmware_host::falcon {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::array<std::byte, 3> kHandshake = {std::byte{0x0A}, std::byte{0x43}, std::byte{0x0D}};
constexpr std::array<std::byte, 4> kHandshakeReply = {std::byte{0x0A}, std::byte{0x44},
                                                      std::byte{0x2C}, std::byte{0x0D}};
constexpr std::byte kProbe{0x41};

// The reply is `0A 44 2C 0D`, optionally preceded by a 0x00 the FTDI does not always deliver.
bool is_handshake_reply(std::span<const std::byte> got) noexcept {
    if (got.size() == 5 && got[0] == std::byte{0}) got = got.subspan(1);
    return got.size() == 4 && std::equal(got.begin(), got.end(), kHandshakeReply.begin());
}

}  // namespace

std::string_view to_string(FirmwareErrc code) noexcept {
    switch (code) {
        case FirmwareErrc::kImageUnreadable:
            return "image_unreadable";
        case FirmwareErrc::kImageEmpty:
            return "image_empty";
        case FirmwareErrc::kImageTooLarge:
            return "image_too_large";
        case FirmwareErrc::kSetupFailed:
            return "setup_failed";
        case FirmwareErrc::kHandshakeFailed:
            return "handshake_failed";
        case FirmwareErrc::kProbeFailed:
            return "probe_failed";
        case FirmwareErrc::kEchoMismatch:
            return "echo_mismatch";
        case FirmwareErrc::kEchoTimeout:
            return "echo_timeout";
        case FirmwareErrc::kWriteFailed:
            return "write_failed";
        case FirmwareErrc::kNormalModeFailed:
            return "normal_mode_failed";
    }
    return "unknown";
}

namespace {

std::string_view sentence(FirmwareErrc code) noexcept {
    switch (code) {
        case FirmwareErrc::kImageUnreadable:
            return "cannot read the firmware image";
        case FirmwareErrc::kImageEmpty:
            return "the firmware image is empty";
        case FirmwareErrc::kImageTooLarge:
            return "the firmware image is larger than 1 MiB";
        case FirmwareErrc::kSetupFailed:
            return "FTDI set-up request failed";
        case FirmwareErrc::kHandshakeFailed:
            return "boot loader did not answer the handshake";
        case FirmwareErrc::kProbeFailed:
            return "boot loader did not answer the baud probe";
        case FirmwareErrc::kEchoMismatch:
            return "firmware chunk echoed back different bytes";
        case FirmwareErrc::kEchoTimeout:
            return "firmware chunk echo did not arrive";
        case FirmwareErrc::kWriteFailed:
            return "bulk write failed";
        case FirmwareErrc::kNormalModeFailed:
            return "switching to normal mode failed";
    }
    return "unknown firmware error";
}

}  // namespace

FirmwareError firmware_error(FirmwareErrc code, std::string path, std::size_t offset,
                             LinkStatus link, int attempts) {
    FirmwareError e;
    e.code = code;
    e.offset = offset;
    e.link = link;
    e.attempts = attempts;
    e.where = path.empty() ? std::string("falcon firmware") : std::move(path);
    e.what = sentence(code);
    if (code == FirmwareErrc::kEchoMismatch || code == FirmwareErrc::kEchoTimeout ||
        code == FirmwareErrc::kWriteFailed) {
        e.what += ": at image offset " + std::to_string(offset);
    }
    if (link != LinkStatus::kOk) e.what += ": " + std::string(to_string(link));
    if (attempts > 0) e.what += " (after " + std::to_string(attempts) + " load attempts)";
    return e;
}

Result<std::vector<std::byte>, FirmwareError> read_firmware_image(const std::filesystem::path& p) {
    auto error = [&p](FirmwareErrc code) { return Err{firmware_error(code, p.string())}; };
    // A regular file only (never a FIFO, a directory or /dev/zero behind a link), read up to one
    // byte past the cap so that "too large" is told apart from "unreadable".
    auto bytes = files::read_regular_file(p, kMaxFirmwareImageBytes + 1);
    if (!bytes) {
        auto e = error(FirmwareErrc::kImageUnreadable);
        e.value.what += ": " + bytes.error().what;
        return e;
    }
    if (bytes->empty()) return error(FirmwareErrc::kImageEmpty);
    if (bytes->size() > kMaxFirmwareImageBytes) return error(FirmwareErrc::kImageTooLarge);
    return std::move(*bytes);
}

std::size_t read_payload(UsbLink& link, std::span<std::byte> out, std::size_t want,
                         std::uint32_t timeout_ms, LinkStatus& last) noexcept {
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
    std::array<std::byte, 512> transfer{};
    std::size_t got = 0;
    want = std::min(want, out.size());
    last = LinkStatus::kOk;
    while (got < want) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) break;
        std::size_t n = 0;
        last = link.bulk_read(transfer, n, static_cast<std::uint32_t>(left.count()) * 1000U);
        if (last == LinkStatus::kTimeout) continue;
        if (last != LinkStatus::kOk) break;
        got += strip_ftdi_status(std::span(transfer).first(n), out.subspan(got, want - got));
    }
    return got;
}

FirmwareLoader::FirmwareLoader(UsbLink& link, std::span<const std::byte> image,
                               FirmwareLoadOptions options)
    : link_(link), image_(image), options_(options) {}

FirmwareLoader::State FirmwareLoader::fail(FirmwareErrc code, LinkStatus link) noexcept {
    failed_code_ = code;
    failed_link_ = link;
    failed_offset_ = offset_;
    failed_attempts_ = attempt_;
    return state_ = State::kFailed;
}

FirmwareError FirmwareLoader::error() const {
    return firmware_error(failed_code_, {}, failed_offset_, failed_link_, failed_attempts_);
}

// A failure inside one load attempt: start over from firmware mode while attempts remain.
FirmwareLoader::State FirmwareLoader::fail_attempt(FirmwareErrc code, LinkStatus link) noexcept {
    if (link == LinkStatus::kDisconnected || attempt_ >= options_.load_attempts)
        return fail(code, link);
    ++attempt_;
    offset_ = 0;
    return state_ = State::kFirmwareMode;
}

FirmwareLoader::State FirmwareLoader::step() noexcept {
    const auto timeout = options_.transfer_timeout_ms;
    switch (state_) {
        case State::kFirmwareMode: {
            const auto s = send_requests(link_, firmware_mode_requests(), timeout);
            if (s != LinkStatus::kOk) return fail(FirmwareErrc::kSetupFailed, s);
            return state_ = State::kHandshake;
        }
        case State::kHandshake:
            return do_handshake();
        case State::kLoadBaud: {
            const auto s = send_requests(link_, firmware_load_requests(), timeout);
            if (s != LinkStatus::kOk) return fail(FirmwareErrc::kSetupFailed, s);
            return state_ = State::kProbe;
        }
        case State::kProbe:
            return do_probe();
        case State::kChunk:
            return do_chunk();
        case State::kNormalMode: {
            const auto s = send_requests(link_, normal_mode_requests(), timeout);
            if (s != LinkStatus::kOk) return fail(FirmwareErrc::kNormalModeFailed, s);
            return state_ = State::kDone;
        }
        case State::kDone:
        case State::kFailed:
            return state_;
    }
    return state_;
}

FirmwareLoader::State FirmwareLoader::do_handshake() noexcept {
    std::array<std::byte, 8> reply{};
    LinkStatus last = LinkStatus::kOk;
    for (int i = 0; i < options_.handshake_tries; ++i) {
        last = link_.bulk_write(kHandshake, options_.transfer_timeout_ms);
        if (last != LinkStatus::kOk) return fail(FirmwareErrc::kWriteFailed, last);
        const auto n = read_payload(link_, reply, 5, options_.transfer_timeout_ms, last);
        if (is_handshake_reply(std::span(reply).first(n))) return state_ = State::kLoadBaud;
        if (last == LinkStatus::kDisconnected) break;
    }
    return fail_attempt(FirmwareErrc::kHandshakeFailed, last);
}

FirmwareLoader::State FirmwareLoader::do_probe() noexcept {
    auto last = link_.bulk_write(std::span(&kProbe, 1), options_.transfer_timeout_ms);
    if (last != LinkStatus::kOk) return fail(FirmwareErrc::kWriteFailed, last);
    std::array<std::byte, 1> reply{};
    const auto n = read_payload(link_, reply, 1, options_.transfer_timeout_ms, last);
    if (n != 1 || reply[0] != kProbe) return fail_attempt(FirmwareErrc::kProbeFailed, last);
    return state_ = State::kChunk;
}

FirmwareLoader::State FirmwareLoader::do_chunk() noexcept {
    if (offset_ >= image_.size()) return state_ = State::kNormalMode;
    const auto chunk =
        image_.subspan(offset_, std::min(kFirmwareChunkSize, image_.size() - offset_));
    auto last = link_.bulk_write(chunk, options_.transfer_timeout_ms);
    if (last != LinkStatus::kOk) return fail_attempt(FirmwareErrc::kWriteFailed, last);
    std::array<std::byte, kFirmwareChunkSize> echo{};
    const auto n = read_payload(link_, echo, chunk.size(), options_.transfer_timeout_ms, last);
    if (n != chunk.size()) return fail_attempt(FirmwareErrc::kEchoTimeout, last);
    if (!std::equal(chunk.begin(), chunk.end(), echo.begin())) {
        return fail_attempt(FirmwareErrc::kEchoMismatch, LinkStatus::kOk);
    }
    offset_ += chunk.size();
    return state_;
}

Status<FirmwareError> load_firmware(UsbLink& link, std::span<const std::byte> image,
                                    const FirmwareLoadOptions& options) {
    if (image.empty()) {
        return Err{firmware_error(FirmwareErrc::kImageEmpty)};
    }
    FirmwareLoader loader(link, image, options);
    // Bounded: each step is bounded and the chunk count and attempts are finite.
    while (loader.state() != FirmwareLoader::State::kDone &&
           loader.state() != FirmwareLoader::State::kFailed) {
        (void)loader.step();
    }
    if (loader.state() == FirmwareLoader::State::kFailed) return Err{loader.error()};
    return {};
}

}  // namespace kerf::firmware_host::falcon
