// Real hidapi and libusb on this machine (usually no haptic device attached): enumeration and
// opening a missing device give clean results, never a crash.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <string>

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
    EXPECT_NE(dev.error().message().find("hid 1209:7ffe"), std::string::npos)
        << dev.error().message();
    EXPECT_NE(dev.error().message().find("no such device connected"), std::string::npos);
    auto by_path = HidapiTransport::open({0, 0, "", "/dev/hidraw-does-not-exist"});
    ASSERT_FALSE(by_path);
    EXPECT_NE(by_path.error().message().find("/dev/hidraw-does-not-exist"), std::string::npos);
}

TEST(RealLibusb, EnumeratesFalconsCleanly) {
    auto falcons = enumerate_usb(falcon::kFalconVendorId, falcon::kFalconProductId);
    if (!falcons) {  // e.g. a container without usbfs: still a clean, named error
        EXPECT_NE(falcons.error().message().find("libusb"), std::string::npos)
            << falcons.error().message();
        return;
    }
    for (const auto& d : *falcons) EXPECT_EQ(d.product_id, falcon::kFalconProductId);
}

TEST(RealLibusb, OpeningAMissingFalconIsAClearError) {
    auto link =
        LibusbLink::open({falcon::kFalconVendorId, falcon::kFalconProductId, "NO-SUCH-SERIAL"});
    ASSERT_FALSE(link);
    const auto m = link.error().message();
    EXPECT_NE(m.find("usb 0403:cb48"), std::string::npos) << m;
}

}  // namespace
}  // namespace kerf::firmware_host

namespace kerf::firmware_host {
namespace {

std::string run(const std::string& command, int& status) {
    std::string out;
    FILE* p = ::popen(command.c_str(), "r");
    if (p == nullptr) return out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
    status = ::pclose(p);
    return out;
}

bool have_kerf() { return ::access(KERF_BIN_DIR "/kerf", X_OK) == 0; }

TEST(KerfDevicesCommand, ListsDevicesOrSaysNoneFoundAgainstRealLibraries) {
    if (!have_kerf()) GTEST_SKIP() << "bin/kerf not built (partial build): build the `kerf` target";
    int status = -1;
    const std::string kerf = std::string(KERF_BIN_DIR) + "/kerf";
    const auto out =
        run(kerf + " devices --devices-dir " KERF_SOURCE_DIR "/config/devices 2>&1", status);
    EXPECT_EQ(status, 0) << out;
    const bool none = out.find("no haptic devices found") != std::string::npos;
    const bool some = out.find("profile") != std::string::npos;
    EXPECT_TRUE(none || some) << out;
    const auto json =
        run(kerf + " devices --json --devices-dir " KERF_SOURCE_DIR "/config/devices", status);
    // One JSON object (nlohmann-json, indented): the folder, the devices, the errors.
    EXPECT_EQ(json.rfind("{\n  \"devices_dir\": ", 0), 0U) << json;
    EXPECT_NE(json.find("\"devices\": ["), std::string::npos) << json;
}

TEST(KerfDevicesCommand, ABadProfileDirectoryIsAClearError) {
    if (!have_kerf()) GTEST_SKIP() << "bin/kerf not built (partial build): build the `kerf` target";
    int status = -1;
    const auto out = run(
        std::string(KERF_BIN_DIR) + "/kerf devices --devices-dir /nonexistent-kerf 2>&1", status);
    EXPECT_NE(status, 0);
    EXPECT_NE(out.find("kerf devices: load device profiles:"), std::string::npos) << out;
    EXPECT_NE(out.find("/nonexistent-kerf"), std::string::npos) << out;
}

}  // namespace
}  // namespace kerf::firmware_host

#include "firmware_host/transport/usb_hotplug.hpp"

namespace kerf::firmware_host {
namespace {

TEST(RealLibusb, HotplugMonitorRegistersAndReportsNoFalconWhenNoneIsPlugged) {
    auto monitor = UsbHotplugMonitor::create(falcon::kFalconVendorId, falcon::kFalconProductId);
    if (!monitor) {  // libusb without hotplug support: a clean, named error
        EXPECT_NE(monitor.error().message().find("usb 0403:cb48"), std::string::npos)
            << monitor.error().message();
        return;
    }
    const auto events = (*monitor)->poll(1000);
    const auto falcons = enumerate_usb(falcon::kFalconVendorId, falcon::kFalconProductId);
    ASSERT_TRUE(falcons);
    EXPECT_EQ(events.arrived, falcons->size());  // LIBUSB_HOTPLUG_ENUMERATE reports present ones
    EXPECT_EQ(events.left, 0U);
}

}  // namespace
}  // namespace kerf::firmware_host
