// The real-time loop allocates nothing: 10,000 ticks of the real configuration — the Kerf HID
// device code talking to the kerf-hapsim process, collision and force on a real CT bone (the
// calcaneus, 58k triangles) built by the WorldBuilder, publishing state, telemetry and events
// into a real session segment and journal — with the allocation counter armed on the loop's
// thread. The builder and journal threads run meanwhile (they may allocate: they are not RT).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <vector>

#include "rt_core/loop/input_recording.hpp"
#include "tests/allocation_counter.hpp"
#include "tests/rt/rt_rig.hpp"

namespace kerf::rt {
namespace {

TEST(RtLoopAllocations, TenThousandTicksOfTheRealConfigurationAllocateNothing) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    // Down into the bone, out, in again: contact, friction, release, a second contact.
    const std::string script =
        "hold,0.05\nmove,0.0,-0.02,0.0,2.0\nmove,0.003,0.0,0.003,2.0\nmove,0.0,-0.02,0.0,"
        "2.0\nhold,10\n";
    test::Rig rig({script, {}, 100'000, true});
    ASSERT_TRUE(rig.ok()) << rig.error();
    std::vector<TraceRow> trace(10'000);
    RunOptions run;
    run.lockstep = true;
    run.max_ticks = 10'000;
    run.trace = trace;
    kerf::test::arm_allocation_counter();
    run_loop(rig.loop(), run);
    const std::uint64_t allocations = kerf::test::disarm_allocation_counter();
    EXPECT_EQ(allocations, 0u);
    const LoopStats& s = rig.loop().stats();
    EXPECT_EQ(s.ticks, 10'000u);
    EXPECT_EQ(s.worlds_swapped, 1u);    // the bone was installed inside the counted ticks
    EXPECT_GT(s.events_published, 0u);  // device state changes at least
    EXPECT_GT(s.compute.count(), 0u);
    EXPECT_EQ(rig.loop().device_state(), ipc::DeviceState::kReady);
    int pushing = 0;  // ticks the bone pushed back: the contact path really ran
    for (const TraceRow& r : trace) pushing += r.force_n[1] > 0.1 ? 1 : 0;
    EXPECT_GT(pushing, 1000) << "the tool never pressed into the bone";
}

// A device lost and re-opened: the loop notices the loss, ticks without a device and installs
// the new one the DeviceReconnector opened on its own thread, all without allocating, while
// every tick is recorded (kerf-rt --record: the recorder's ring, drained by its own thread). The
// counter is disarmed only while the test thread talks to the emulator (its commands allocate).
TEST(RtLoopAllocations, LosingAndReinstallingTheDeviceAllocatesNothing) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    const char* script =
        "hold,0.05\nmove,0.0,-0.02,0.0,0.4\nhold,1.0\nmove,0.0,0.0,0.0,0.3\nhold,0.3\n"
        "move,0.0,-0.02,0.0,0.4\nhold,60\n";
    test::Rig rig({script, {}, 20'000, true});
    ASSERT_TRUE(rig.ok()) << rig.error();
    const std::string file = (std::filesystem::temp_directory_path() /
                              ("kerf-alloc-rec-" + std::to_string(getpid()) + ".rec"))
                                 .string();
    auto recorder = InputRecorder::start(file, 1'000'000);
    ASSERT_TRUE(recorder) << recorder.error();
    rig.loop().record_to(recorder->get());
    std::uint64_t allocations = 0;
    const auto ticks_counted = [&](int n, auto until) {
        kerf::test::arm_allocation_counter();
        int i = 0;
        for (; i < n && !until(); ++i) rig.tick();
        allocations += kerf::test::disarm_allocation_counter();
        return i < n;
    };
    ASSERT_TRUE(ticks_counted(4000, [&] { return rig.force_norm() > 0.05; }));
    ASSERT_TRUE(rig.sim().command("fault unplug on"));
    ASSERT_TRUE(ticks_counted(2000, [&] { return rig.loop().waiting_for_device(); }));
    ticks_counted(50, [] { return false; });  // 50 ticks without a device
    ASSERT_TRUE(rig.sim().command("fault unplug off"));
    EXPECT_TRUE(ticks_counted(6000, [&] {
        return rig.loop().stats().devices_reopened == 1 && rig.force_norm() > 0.05;
    })) << "no force from the re-opened device";
    EXPECT_EQ(allocations, 0u);
    EXPECT_EQ(rig.loop().stats().devices_lost, 1u);
    EXPECT_GE(rig.loop().stats().device_lost_ticks, 50u);
    auto recorded = (*recorder)->stop();
    ASSERT_TRUE(recorded) << recorded.error();
    EXPECT_EQ(*recorded, rig.loop().stats().ticks) << "every tick recorded, lost ones included";
    std::filesystem::remove(file);
}

}  // namespace
}  // namespace kerf::rt
