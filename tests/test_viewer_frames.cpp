// The viewer's moving frames (apps/view_renderer): the preview at 1/N of the resolution is `igi`
// rendered at that resolution, each pixel repeated over N x N; the full-resolution frame is
// `igi` at the view's size. Both against renders made here from the options the viewer
// documents (README, "Look around a scene first"), not from the viewer's own options.
#include <gtest/gtest.h>

#include "render_helpers.h"
#include "scene/scene.h"
#include "view_renderer.h"
#include "vpl_test_scenes.h"

namespace ml {
namespace {

constexpr int kWidth = 27, kHeight = 19;

std::string viewer_test_scene() {
    return R"(LookAt 0 1.2 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 27 ] "integer yresolution" [ 19 ]
Sampler "independent"
WorldBegin
)" + vpl_test::mixed_box();
}

// igi as the viewer's moving frames run it: 1 spp, the sliders' settings, one light sample of
// the direct light per pixel (and a BSDF sample with MIS on glossy surfaces only) blurred with
// the VPLs' light.
RenderOutput igi_frame(const Scene& scene, const std::array<float, 9>& view, const ViewSettings& s,
                       int width, int height) {
    RenderOptions o;
    o.integrator = "igi";
    o.spp = 1;
    o.threads = 2;
    o.width = width;
    o.height = height;
    o.look_at = view;
    o.set = {{"igi.vpls", std::to_string(s.vpls)},     {"igi.interleave", s.interleave},
             {"igi.filter", std::to_string(s.filter)}, {"lights.direct_samples", "1"},
             {"lights.direct_mis", "glossy"},          {"igi.filter_direct", "true"}};
    return render_built_scene(scene, o);
}

TEST(ViewerFrames, PreviewIsIgiAtTheReducedResolutionAndFullIsIgi) {
    Scene scene(parse_scene_string(viewer_test_scene(), "."));
    ViewConfig config;
    config.width = kWidth;
    config.height = kHeight;
    config.threads = 2;
    ViewRenderer viewer(scene, config);
    ViewSettings s = viewer.settings();
    s.vpls = 64;
    s.interleave = "2x2";
    const std::array<float, 9> view = {0.2f, 1.1f, -3.8f, 0, 0.5f, 0, 0, 1, 0};
    for (int divider : {1, 2, 3}) {
        ViewRenderer::MovingFrame frame = viewer.moving_frame(view, s, divider);
        ASSERT_EQ(frame.image.width, kWidth);
        ASSERT_EQ(frame.image.height, kHeight);
        // Rounded up: 27x19 at 1/2 is 14x10, at 1/3 9x7.
        const int w = (kWidth + divider - 1) / divider, h = (kHeight + divider - 1) / divider;
        Image small = igi_frame(scene, view, s, w, h).image;
        double sum = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const RGB& a = frame.image.at(x, y);
                const RGB& b = small.at(x / divider, y / divider);
                sum += a.r + a.g + a.b;
                ASSERT_EQ(a.r, b.r) << "divider " << divider << " pixel " << x << "," << y;
                ASSERT_EQ(a.g, b.g) << "divider " << divider << " pixel " << x << "," << y;
                ASSERT_EQ(a.b, b.b) << "divider " << divider << " pixel " << x << "," << y;
            }
        EXPECT_GT(sum, 0) << "divider " << divider;
    }
    // A preview pixel covers divider x divider of the view's: neighbours within a block agree,
    // and the preview differs from the full frame (fewer, larger pixels).
    Image full = viewer.moving_frame(view, s, 1).image;
    Image preview = viewer.moving_frame(view, s, 2).image;
    EXPECT_EQ(preview.at(4, 6).r, preview.at(5, 7).r);
    EXPECT_NE(preview.pixels, full.pixels);
}

}  // namespace
}  // namespace ml
