// Real hidapi and libusb on this machine (usually no haptic device attached): enumeration and
// opening a missing device give clean results, never a crash.
#include <gtest/gtest.h>

#include "firmware_host/falcon/ftdi.hpp"
#include "firmware_host/transport/hidapi_transport.hpp"
#include "firmware_host/transport/libusb_link.hpp"

namespace kerf::firmware_host {
namespace {

TEST(RealHidapi, EnumeratesWithoutCrashing) {
    auto all = enumerate_hid(0, 0);
    ASSERT_TRUE(all) << all.error().message();  // hidapi-hidraw starts even without devices
    auto kerf = enumerate_hid(0x1209, 0x0001);
    ASSERT_TRUE(kerf);
    for (const auto& d : *kerf) EXPECT_EQ(d.vendor_id, 0x1209);
}

TEST(RealHidapi, OpeningAMissingDeviceIsAClearError) {
    auto dev = HidapiTransport::open({0x1209, 0x7FFE, "", ""});
    ASSERT_FALSE(dev);
    EXPECT_NE(dev.error().message().find("hid 1209:7ffe"), std::string::npos) << dev.error().message();
    EXPECT_NE(dev.error().message().find("no such device connected"), std::string::npos);
    auto by_path = HidapiTransport::open({0, 0, "", "/dev/hidraw-does-not-exist"});
    ASSERT_FALSE(by_path);
    EXPECT_NE(by_path.error().message().find("/dev/hidraw-does-not-exist"), std::string::npos);
}

TEST(RealLibusb, EnumeratesFalconsCleanly) {
    auto falcons = enumerate_usb(falcon::kFalconVendorId, falcon::kFalconProductId);
    if (!falcons) {  // e.g. a container without usbfs: still a clean, named error
        EXPECT_NE(falcons.error().message().find("libusb"), std::string::npos) << falcons.error().message();
        return;
    }
    for (const auto& d : *falcons) EXPECT_EQ(d.product_id, falcon::kFalconProductId);
}

TEST(RealLibusb, OpeningAMissingFalconIsAClearError) {
    auto link = LibusbLink::open({falcon::kFalconVendorId, falcon::kFalconProductId, "NO-SUCH-SERIAL"});
    ASSERT_FALSE(link);
    const auto m = link.error().message();
    EXPECT_NE(m.find("usb 0403:cb48"), std::string::npos) << m;
}

}  // namespace
}  // namespace kerf::firmware_host
