// Renderer on a real headless EGL context (Mesa llvmpipe, surfaceless platform): clear, draw,
// upload counts, blade, HUD, screenshot.
#include "display/render/renderer.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "display/egl/egl_output.hpp"
#include "tests/render/render_scenes.hpp"

namespace kerf::render {
namespace {

using testing::SceneKind;

struct Pixel {
    int r, g, b;
};
Pixel at(const std::vector<std::uint8_t>& rgba, int w, int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(y) * w + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2]};
}

class RendererTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto out = egl::EglOutput::create({});
        ASSERT_TRUE(out) << out.error().message();
        output_ = std::make_unique<egl::EglOutput>(std::move(*out));
        auto r = Renderer::create({kW, kH});
        ASSERT_TRUE(r) << r.error().message();
        renderer_ = std::make_unique<Renderer>(std::move(*r));
    }
    static constexpr int kW = 320, kH = 240;
    std::unique_ptr<egl::EglOutput> output_;
    std::unique_ptr<Renderer> renderer_;
};

TEST_F(RendererTest, HeadlessNeedsNoEnvironmentAndReportsItsRenderer) {
    EXPECT_EQ(output_->platform(), egl::EglPlatform::kHeadless);
    EXPECT_NE(output_->description().find("headless: "), std::string::npos);
    EXPECT_NE(output_->description().find("OpenGL ES 3"), std::string::npos);
}

TEST_F(RendererTest, AnEmptyFrameIsTheBackgroundColour) {
    renderer_->begin_frame(Camera::framing({-1, -1, -1}, {1, 1, 1}));
    renderer_->finish_frame();
    const auto px = renderer_->read_pixels();
    ASSERT_EQ(px.size(), std::size_t{kW} * kH * 4);
    const Pixel p = at(px, kW, kW / 2, kH / 2);
    EXPECT_NEAR(p.r, 0.10 * 255, 2);
    EXPECT_NEAR(p.g, 0.12 * 255, 2);
    EXPECT_NEAR(p.b, 0.15 * 255, 2);
}

TEST_F(RendererTest, DrawsTheBoneInTheMiddleAndTheHudTopLeft) {
    auto s = testing::make_scene(SceneKind::kUncut, 20000);
    s.planned.reset();
    testing::draw_scene(*renderer_, s, true);
    const auto px = renderer_->read_pixels();
    const Pixel bone = at(px, kW, kW / 2, kH / 2);
    EXPECT_GT(bone.r, 120);     // lit ivory, much brighter than the background
    EXPECT_GT(bone.r, bone.b);  // warm, not grey or blue
    int hud_ink = 0;            // light text pixels in the HUD corner
    for (int y = 10; y < 40; ++y)
        for (int x = 10; x < 200; ++x) hud_ink += at(px, kW, x, y).g > 200;
    EXPECT_GT(hud_ink, 50);
}

TEST_F(RendererTest, AnAbandonedFrameBegunAgainDrawsWhatAnUninterruptedOneDraws) {
    auto s = testing::make_scene(SceneKind::kUncut, 100000);  // several chunks of draw calls
    ASSERT_GT(s.render.triangle_count(), 2 * kBoneChunkTriangles);
    s.planned.reset();
    testing::draw_scene(*renderer_, s, false);
    const auto uninterrupted = renderer_->read_pixels();
    // Abandoned after the first chunk (kerf-display: an edit arrived), then begun again.
    int asked = 0;
    EXPECT_FALSE(renderer_->begin_frame(s.camera, [&] { return ++asked == 1; }));
    EXPECT_EQ(asked, 1) << "asked between chunks, stopped at the first yes";
    asked = 0;
    EXPECT_TRUE(renderer_->begin_frame(s.camera, [&] { return ++asked < 0; }));
    EXPECT_EQ(asked,
              int((s.render.triangle_count() + kBoneChunkTriangles - 1) / kBoneChunkTriangles))
        << "asked once after every chunk";
    renderer_->draw_blade(s.blade);
    renderer_->finish_frame();
    EXPECT_EQ(renderer_->read_pixels(), uninterrupted);
}

/// A frame of `s` with nothing pending: clear, bone, blade, finish; its pixels.
std::vector<std::uint8_t> fresh_frame(Renderer& r, testing::Scene& s) {
    r.begin_frame(s.camera);
    r.draw_blade(s.blade);
    r.finish_frame();
    return r.read_pixels();
}

TEST_F(RendererTest, AnEditJoiningTheFrameInFlightDrawsWhatAFrameBegunAfterItDraws) {
    auto s = testing::make_scene(SceneKind::kUncut, 100000);
    s.planned.reset();
    ASSERT_GT(s.render.triangle_count(), 2 * kBoneChunkTriangles);
    renderer_->upload(s.render);
    const auto before = fresh_frame(*renderer_, s);
    cut::CutContext ctx(s.mesh);
    const auto cut_at = [&](double z) {  // a cut through, its kerf opened: visible
        cut::CrossSection cs;
        const auto plane = *cut::Plane::make({0.0, 0.0, z}, {0.0, 0.15, 1.0});
        EXPECT_TRUE(cut::slice_by_plane(ctx, plane, cs).ok());
        auto sep = cut::Separator::make(ctx, cs, 2 * testing::kKerf);
        ASSERT_TRUE(sep);
        sep->sweep_all();
        s.mesh.update_normals();
        s.render.update_after_edit(s.mesh, sep->moved_vertices());
    };
    // After the first chunk (the start of the tube) an edit arrives near the far end: it touches
    // nothing drawn yet, so it joins the frame, and the frame shows it.
    int asked = 0, joined = 0;
    UploadStats up;
    EXPECT_TRUE(renderer_->begin_frame(s.camera, [&] {
        if (++asked == 1) {
            cut_at(0.9 * testing::kLength);
            joined += renderer_->join_frame(s.render, up) ? 1 : 0;
        }
        return false;
    }));
    renderer_->draw_blade(s.blade);
    renderer_->finish_frame();
    const auto with_join = renderer_->read_pixels();
    EXPECT_EQ(joined, 1) << "the edit touched no issued triangle: it should have joined";
    EXPECT_GT(up.bytes, 0u);
    EXPECT_NE(with_join, before) << "the edit changed nothing on screen";
    EXPECT_EQ(with_join, fresh_frame(*renderer_, s)) << "the joined frame differs";

    // An edit of the part already drawn (near the start) cannot join: the frame begins again.
    asked = 0;
    bool refused = false;
    EXPECT_FALSE(renderer_->begin_frame(s.camera, [&] {
        if (++asked > 1) return false;
        cut_at(0.05 * testing::kLength);
        refused = !renderer_->join_frame(s.render, up);
        return refused;
    }));
    EXPECT_TRUE(refused);
    renderer_->upload(s.render);
    EXPECT_NE(fresh_frame(*renderer_, s), with_join) << "the second cut changed nothing?";
}

TEST_F(RendererTest, UploadsOnlyDirtyRangesAfterACut) {
    auto s = testing::make_scene(SceneKind::kUncut, 20000);
    const UploadStats first = renderer_->upload(s.render);
    EXPECT_TRUE(first.reallocated);
    const UploadStats idle = renderer_->upload(s.render);
    EXPECT_EQ(idle.bytes, 0u);
    cut::CutContext ctx(s.mesh);
    cut::CrossSection cs;
    ASSERT_TRUE(cut::slice_by_plane(ctx, testing::scene_plane(), cs).ok());
    s.render.update_after_edit(s.mesh);
    const UploadStats after = renderer_->upload(s.render);
    EXPECT_FALSE(after.reallocated);
    EXPECT_GT(after.bytes, 0u);
    EXPECT_LT(after.bytes, first.bytes / 4);
    EXPECT_GT(after.calls, 0u);
}

TEST_F(RendererTest, ScreenshotIsAPngOfTheFramebuffer) {
    auto s = testing::make_scene(SceneKind::kMidCut, 20000);
    testing::draw_scene(*renderer_, s, false);
    const auto path = std::filesystem::temp_directory_path() / "kerf_render_test_shot.png";
    ASSERT_TRUE(renderer_->save_png(path.string()));
    int w = 0, h = 0, n = 0;
    unsigned char* img = stbi_load(path.c_str(), &w, &h, &n, 4);
    ASSERT_NE(img, nullptr);
    EXPECT_EQ(w, kW);
    EXPECT_EQ(h, kH);
    const auto px = renderer_->read_pixels();
    EXPECT_EQ(0, std::memcmp(img, px.data(), px.size()));
    stbi_image_free(img);
    std::filesystem::remove(path);
}

TEST_F(RendererTest, ScreenshotIntoAMissingFolderFailsByName) {
    renderer_->begin_frame(Camera::framing({-1, -1, -1}, {1, 1, 1}));
    const auto st = renderer_->save_png("/nonexistent-kerf-dir/shot.png");
    ASSERT_FALSE(st);
    EXPECT_NE(st.error().message().find("/nonexistent-kerf-dir/shot.png"), std::string::npos);
}

}  // namespace
}  // namespace kerf::render
