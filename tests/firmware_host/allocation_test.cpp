// Zero heap allocation after open: 10,000 ticks of read -> safety -> write against kerf-hapsim
// (a real process, lockstep) for both device kinds, counted by a replaced operator new.
// malloc() calls made directly by C libraries are not counted (hidapi/libusb are not on this path).
#include <gtest/gtest.h>

#include "firmware_host/device/falcon_device.hpp"
#include "firmware_host/device/kerf_hid_device.hpp"
#include "firmware_host/transport/socket_report_transport.hpp"
#include "firmware_host/transport/socket_usb_link.hpp"
#include "tests/allocation_counter.hpp"
#include "tests/firmware_host/device_loop.hpp"
#include "tests/firmware_host/hapsim_process.hpp"

namespace kerf::firmware_host {
namespace {

std::uint64_t count_allocations(Device& dev, int ticks) {
    test::DeviceLoop loop(dev);
    loop.desired = {0, 0, 0};
    for (int i = 0; i < 100; ++i) loop.tick();  // homing, engagement: same code path anyway
    kerf::test::arm_allocation_counter();
    for (int i = 0; i < ticks; ++i) {
        loop.desired = {0.5 * (i % 7), 0, 1.0};
        loop.tick();
    }
    return kerf::test::disarm_allocation_counter();
}

TEST(AllocationCounter, CountsAnAllocationOnThisThread) {
    kerf::test::arm_allocation_counter();
    int* volatile p = new int(3);  // volatile: the compiler may not elide this allocation
    delete p;
    EXPECT_EQ(kerf::test::disarm_allocation_counter(), 1U);
}

TEST(ZeroAllocation, KerfHidDeviceTicksTenThousandTimesWithoutAllocating) {
    test::HapsimProcess sim({"--protocol", "kerf"});
    ASSERT_TRUE(sim.ready());
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    ASSERT_TRUE(socket);
    auto dev = KerfHidDevice::open(std::make_unique<SocketReportTransport>(std::move(*socket)), {});
    ASSERT_TRUE(dev) << dev.error().message();
    EXPECT_EQ(count_allocations(**dev, 10000), 0U);
}

TEST(ZeroAllocation, FalconDeviceTicksTenThousandTimesWithoutAllocating) {
    test::HapsimProcess sim({"--protocol", "falcon", "--firmware-loaded"});
    ASSERT_TRUE(sim.ready());
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    ASSERT_TRUE(socket);
    auto dev = FalconDevice::open(std::make_unique<SocketUsbLink>(std::move(*socket)), {});
    ASSERT_TRUE(dev) << dev.error().message();
    EXPECT_EQ(count_allocations(**dev, 10000), 0U);
}

}  // namespace
}  // namespace kerf::firmware_host
