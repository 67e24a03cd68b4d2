// The concurrent parts of kerf-rt on real threads (run under TSan in CI): the wait-free Handoff
// (builder thread offers, loop thread takes and retires, builder frees), and the WorldBuilder
// reading meshes a display thread publishes through the real mailbox while a loop thread swaps
// the worlds in and queries them every "tick".
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "rt_core/loop/collision_mesh_builder.hpp"
#include "rt_core/loop/device_reconnector.hpp"
#include "rt_core/loop/handoff.hpp"
#include "rt_core/loop/world_builder.hpp"

namespace kerf::rt {
namespace {

std::atomic<int> g_alive{0};

struct Counted {
    explicit Counted(std::uint64_t v) : value(v) { g_alive.fetch_add(1); }
    ~Counted() { g_alive.fetch_sub(1); }
    std::uint64_t value;
    std::uint64_t payload[8] = {};  // written by the offering thread, read by the taking one
};

/// A device that only counts (the thread-safety of the re-open hand-off is the point here; the
/// real devices are re-opened against kerf-hapsim in kerf_rt_integration_tests).
struct CountingDevice final : firmware_host::Device {
    explicit CountingDevice(std::uint64_t g) : generation(g) { g_alive.fetch_add(1); }
    ~CountingDevice() override { g_alive.fetch_sub(1); }
    firmware_host::DeviceStatus try_read(firmware_host::DeviceSample&,
                                         std::uint32_t) noexcept override {
        return firmware_host::DeviceStatus::kDisconnected;
    }
    firmware_host::DeviceStatus try_write(const firmware_host::DeviceCommand&) noexcept override {
        return firmware_host::DeviceStatus::kOk;
    }
    const firmware_host::DeviceCounters& counters() const noexcept override { return c; }
    std::uint64_t generation;
    firmware_host::DeviceCounters c;
};

// The loop thread loses its device again and again; the reconnector thread opens a new one each
// time (failing every other attempt) and hands it over; the loop installs it and retires the
// old one, which the reconnector frees. No device is opened twice for one loss; all are freed.
TEST(RtDeviceReconnector, EveryLossGetsOneNewDeviceAndEveryOldOneIsFreed) {
    {
        Handoff<DeviceSlot> handoff;
        DeviceLink link;
        std::atomic<std::uint64_t> opened{0}, calls{0};
        DeviceReconnector reconnector(
            link, handoff,
            [&]() -> Result<std::unique_ptr<firmware_host::Device>, std::string> {
                if (calls.fetch_add(1) % 2 == 0) return Err{std::string("not there yet")};
                return std::unique_ptr<firmware_host::Device>(
                    std::make_unique<CountingDevice>(opened.fetch_add(1) + 1));
            },
            ReopenBackoff{1, 2, 1});
        reconnector.start();
        DeviceSlot* current = nullptr;
        constexpr std::uint64_t kLosses = 200;
        for (std::uint64_t loss = 1; loss <= kLosses; ++loss) {
            link.report_lost();
            DeviceSlot* next = nullptr;
            while ((next = handoff.try_take()) == nullptr) std::this_thread::yield();
            ASSERT_EQ(next->generation, loss);
            ASSERT_EQ(static_cast<CountingDevice*>(next->device.get())->generation, loss);
            ASSERT_TRUE(handoff.retire(current));
            current = next;
            link.report_installed(next->generation);
        }
        reconnector.stop();
        EXPECT_EQ(opened.load(), kLosses);
        EXPECT_EQ(reconnector.stats().reopened, kLosses);
        EXPECT_GE(reconnector.stats().failures, kLosses);
        handoff.retire(current);
    }
    EXPECT_EQ(g_alive.load(), 0);
}

TEST(RtHandoff, TheLoopSeesNewerObjectsOnlyAndEveryObjectIsFreed) {
    {
        Handoff<Counted> handoff;
        std::atomic<bool> done{false};
        std::thread builder([&] {
            for (std::uint64_t i = 1; i <= 20'000; ++i) {
                auto c = std::make_unique<Counted>(i);
                for (auto& p : c->payload) p = i;
                handoff.offer(std::move(c));
                handoff.collect();
            }
            done = true;
        });
        Counted* current = nullptr;
        std::uint64_t taken = 0, last = 0;
        while (!done.load() || handoff.pending()) {
            if (Counted* next = handoff.try_take()) {
                ASSERT_GT(next->value, last);
                for (auto p : next->payload) ASSERT_EQ(p, next->value);
                last = next->value;
                ASSERT_TRUE(handoff.retire(current));
                current = next;
                ++taken;
            }
        }
        builder.join();
        EXPECT_GT(taken, 0u);
        EXPECT_EQ(last, 20'000u);
        handoff.retire(current);
    }
    EXPECT_EQ(g_alive.load(), 0);
}

/// A closed octahedron of radius `r` (m) as a one-body collision mesh.
void octahedron(ipc::CollisionMesh& m, float r) {
    const float v[18] = {r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r};
    const std::uint32_t t[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                                 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    const std::uint8_t mat[8] = {0, 0, 0, 0, 1, 1, 1, 2};
    std::array<float, 16> pose{};
    pose[0] = pose[5] = pose[10] = pose[15] = 1.f;
    m.body_count = m.vertex_count = m.index_count = 0;
    ASSERT_TRUE(append_body(m, v, t, mat, pose));
}

TEST(RtWorldBuilder, MeshesPublishedByADisplayThreadAreSwappedInWhileTheLoopQueries) {
    auto seg = ipc::SegmentBuilder().name("kerf.rt-conc-" + std::to_string(getpid())).create();
    ASSERT_TRUE(seg) << seg.error().message();
    Handoff<WorldSnapshot> handoff;
    WorldBuilder builder(handoff, seg->layout());
    builder.start(1);
    constexpr int kGenerations = 40;
    std::atomic<bool> published{false};
    std::thread display([&] {
        ipc::MeshMailboxWriter writer(seg->layout());
        auto mesh = std::make_unique<ipc::CollisionMesh>();
        for (int g = 1; g <= kGenerations; ++g) {
            octahedron(*mesh, 0.01f + 0.001f * float(g));
            ASSERT_TRUE(writer.publish(*mesh));
            std::this_thread::sleep_for(std::chrono::milliseconds(3));
        }
        published = true;
    });
    physics::CollisionWorld world;
    WorldSnapshot* current = nullptr;
    std::uint64_t last_generation = 0;
    int queries_hit = 0;
    for (int tick = 0; tick < 200'000 && last_generation < kGenerations; ++tick) {
        if (WorldSnapshot* next = handoff.try_take()) {
            ASSERT_GT(next->generation, last_generation);
            last_generation = next->generation;
            world.set_body(0, next->bodies[0].get());
            world.set_pose(0, next->poses[0]);
            ASSERT_TRUE(handoff.retire(current));
            current = next;
        }
        if (current) {
            const physics::SurfaceHit hit = world.closest_point({0.05, 0, 0}, 0.1);
            queries_hit += hit.found ? 1 : 0;
        }
        if (tick % 64 == 0) std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    display.join();
    builder.stop();
    handoff.retire(current);
    EXPECT_EQ(last_generation, std::uint64_t(kGenerations));
    EXPECT_GT(queries_hit, 0);
    EXPECT_EQ(builder.stats().rejected, 0u);
}

}  // namespace
}  // namespace kerf::rt
