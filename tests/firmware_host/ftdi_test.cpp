#include "firmware_host/falcon/ftdi.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "firmware_host/falcon/firmware_loader.hpp"

namespace kerf::firmware_host::falcon {
namespace {

TEST(FtdiStatusBytes, AreStrippedAtTheStartOfEvery64BytePacket) {
    std::vector<std::byte> transfer(64 + 64 + 10);
    for (std::size_t i = 0; i < transfer.size(); ++i)
        transfer[i] = std::byte{static_cast<std::uint8_t>(i)};
    std::array<std::byte, 256> out{};
    const auto n = strip_ftdi_status(transfer, out);
    ASSERT_EQ(n, 62U + 62U + 8U);
    EXPECT_EQ(out[0], std::byte{2});
    EXPECT_EQ(out[61], std::byte{63});
    EXPECT_EQ(out[62], std::byte{66});  // bytes 64 and 65 were the second packet's status
    EXPECT_EQ(out[124], std::byte{130});
}

TEST(FtdiStatusBytes, AStatusOnlyTransferHasNoPayloadAndOutputIsBounded) {
    const std::array<std::byte, 2> status = {std::byte{0x31}, std::byte{0x60}};
    std::array<std::byte, 4> out{};
    EXPECT_EQ(strip_ftdi_status(status, out), 0U);
    std::vector<std::byte> big(64, std::byte{7});
    EXPECT_EQ(strip_ftdi_status(big, out), out.size());
}

// A link whose device refuses every control request and never sends anything.
class DeadLink final : public UsbLink {
public:
    LinkStatus control_transfer(std::uint8_t, std::uint8_t request, std::uint16_t, std::uint16_t,
                                std::uint32_t) noexcept override {
        requests.push_back(request);
        return stall_controls ? LinkStatus::kStall : LinkStatus::kOk;
    }
    LinkStatus bulk_write(std::span<const std::byte>, std::uint32_t) noexcept override {
        return LinkStatus::kOk;
    }
    LinkStatus bulk_read(std::span<std::byte>, std::size_t& n, std::uint32_t) noexcept override {
        n = 0;
        return LinkStatus::kTimeout;
    }
    bool stall_controls = true;
    std::vector<std::uint8_t> requests;
};

TEST(FirmwareLoader, AStalledSetupRequestIsAClearError) {
    DeadLink link;
    const std::vector<std::byte> image(100, std::byte{1});
    auto s = load_firmware(link, image, {50, 2, 2});
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, FirmwareErrc::kSetupFailed);
    EXPECT_NE(s.error().message().find("device refused the request"), std::string::npos)
        << s.error().message();
    EXPECT_EQ(link.requests.front(), ftdi::kReset);
}

TEST(FirmwareLoader, ASilentBootLoaderFailsTheHandshakeAfterEveryAttempt) {
    DeadLink link;
    link.stall_controls = false;
    const std::vector<std::byte> image(100, std::byte{1});
    FirmwareLoader loader(link, image, {1, 2, 3});
    while (loader.state() != FirmwareLoader::State::kDone &&
           loader.state() != FirmwareLoader::State::kFailed) {
        loader.step();
    }
    ASSERT_EQ(loader.state(), FirmwareLoader::State::kFailed);
    EXPECT_EQ(loader.error().code, FirmwareErrc::kHandshakeFailed);
    EXPECT_EQ(loader.attempts(), 3);
    EXPECT_NE(loader.error().message().find("after 3 load attempts"), std::string::npos);
}

TEST(FirmwareLoader, AnEmptyOrMissingImageIsRefusedBeforeTouchingTheDevice) {
    DeadLink link;
    EXPECT_FALSE(load_firmware(link, {}, {}));
    EXPECT_TRUE(link.requests.empty());
    auto image = read_firmware_image("/nonexistent/novint.bin");
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().message().find("/nonexistent/novint.bin"), std::string::npos);
    auto dir = read_firmware_image("/tmp");
    ASSERT_FALSE(dir);
    EXPECT_EQ(dir.error().code, FirmwareErrc::kImageUnreadable);
}

// Issue 9, item 4: the image is read like every input — a link to /dev/zero is refused at once
// (it used to read until memory ran out), a FIFO is refused without waiting for a writer.
TEST(FirmwareLoader, ALinkToADeviceOrAFifoIsRefusedWithoutReading) {
    char tmpl[] = "/tmp/kerf-fw-XXXXXX";
    const std::filesystem::path dir = mkdtemp(tmpl);
    std::filesystem::create_symlink("/dev/zero", dir / "zero.bin");
    ASSERT_EQ(mkfifo((dir / "fifo.bin").c_str(), 0600), 0);
    auto zero = read_firmware_image(dir / "zero.bin");
    ASSERT_FALSE(zero);
    EXPECT_EQ(zero.error().code, FirmwareErrc::kImageUnreadable);
    EXPECT_NE(zero.error().message().find(
                  "zero.bin: cannot read the firmware image: is a character device"),
              std::string::npos)
        << zero.error().message();
    auto fifo = read_firmware_image(dir / "fifo.bin");
    ASSERT_FALSE(fifo);
    EXPECT_NE(fifo.error().message().find("FIFO"), std::string::npos) << fifo.error().message();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace kerf::firmware_host::falcon
