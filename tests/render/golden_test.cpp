// Golden images of fixed scenes (<= 100k triangles) on headless llvmpipe: an uncut bone with its
// planned cut, a bone mid-cut with the blade in the kerf, a severed piece moved. Compared with a
// tolerance: llvmpipe is deterministic for one Mesa version, other versions differ slightly.
//
// Regenerate after an intended visual change (then LOOK at the PNGs before committing):
//   KERF_UPDATE_GOLDEN=1 build/bin/kerf_render_golden_tests
// Every run writes what it rendered to <build>/render-actual/<name>.png for inspection.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cstdlib>
#include <filesystem>

#include "display/egl/egl_output.hpp"
#include "tests/render/render_scenes.hpp"

namespace kerf::render {
namespace {

using testing::SceneKind;

constexpr int kW = 400, kH = 300;
constexpr int kChannelTolerance = 24;           // per-channel difference that counts as "differs"
constexpr double kMaxDifferingFraction = 0.01;  // of all pixels

struct Golden {
    const char* name;
    SceneKind kind;
};

class GoldenTest : public ::testing::TestWithParam<Golden> {};

TEST_P(GoldenTest, MatchesTheStoredImage) {
    auto out = egl::EglOutput::create({});
    ASSERT_TRUE(out) << out.error().message();
    auto r = Renderer::create({kW, kH});
    ASSERT_TRUE(r) << r.error().message();
    auto scene = testing::make_scene(GetParam().kind, 60000);
    ASSERT_LE(scene.render.triangle_count(), 100000u);
    testing::draw_scene(*r, scene, true);
    const auto px = r->read_pixels();

    const std::filesystem::path actual_dir =
        std::filesystem::path(KERF_BIN_DIR) / ".." / "render-actual";
    std::filesystem::create_directories(actual_dir);
    const auto actual = actual_dir / (std::string(GetParam().name) + ".png");
    ASSERT_TRUE(write_png(actual.string(), kW, kH, px));
    const auto golden = std::filesystem::path(KERF_SOURCE_DIR) / "tests/render/golden" /
                        (std::string(GetParam().name) + ".png");
    if (std::getenv("KERF_UPDATE_GOLDEN")) {
        ASSERT_TRUE(write_png(golden.string(), kW, kH, px));
        GTEST_SKIP() << "golden rewritten: " << golden;
    }
    int w = 0, h = 0, n = 0;
    unsigned char* img = stbi_load(golden.c_str(), &w, &h, &n, 4);
    ASSERT_NE(img, nullptr) << "no golden image " << golden << " (KERF_UPDATE_GOLDEN=1 makes it)";
    ASSERT_EQ(w, kW);
    ASSERT_EQ(h, kH);
    std::size_t differing = 0;
    int worst = 0;
    for (std::size_t i = 0; i < px.size(); i += 4) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int{px[i + c]} - int{img[i + c]}));
        worst = std::max(worst, d);
        differing += d > kChannelTolerance;
    }
    stbi_image_free(img);
    const double fraction = static_cast<double>(differing) / (kW * kH);
    EXPECT_LE(fraction, kMaxDifferingFraction)
        << differing << " pixels differ by more than " << kChannelTolerance << " (worst " << worst
        << "); compare " << actual << " with " << golden;
}

INSTANTIATE_TEST_SUITE_P(Scenes, GoldenTest,
                         ::testing::Values(Golden{"uncut_bone", SceneKind::kUncut},
                                           Golden{"bone_mid_cut", SceneKind::kMidCut},
                                           Golden{"severed_piece_moved", SceneKind::kSevered}),
                         [](const auto& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace kerf::render
