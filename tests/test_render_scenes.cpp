// Every shared scene loads and renders with `path`: a small image, every pixel finite and
// non-negative, and light reaching the camera.
#include <gtest/gtest.h>

#include "render_helpers.h"
#include "shared_files.h"

using namespace ml;

namespace {

void expect_renders(const std::string& scene, int w, int h) {
    ML_NEED_SHARED("scenes/" + scene);  // a skip here ends the (void) helper and the test
    RenderOptions opt;
    opt.integrator = "path";
    opt.spp = 2;
    opt.width = w;
    opt.height = h;
    opt.progress = false;
    RenderOutput out =
        render_scene(parse_scene_file(ml::test::shared_dir() + "/scenes/" + scene), opt);
    ASSERT_EQ(out.image.width, w);
    double sum = 0;
    for (const RGB& p : out.image.pixels) {
        ASSERT_TRUE(p.is_finite()) << scene;
        ASSERT_GE(std::min({p.r, p.g, p.b}), 0.f) << scene;
        sum += p.average();
    }
    EXPECT_GT(sum / out.image.pixels.size(), 1e-3) << scene;
    EXPECT_GT(out.figures.triangles, 0u);
    EXPECT_EQ(out.figures.nonfinite_samples, 0u) << scene;  // the film drops and counts them
}

}  // namespace

TEST(RenderScenes, CornellBox) { expect_renders("cornell-box/scene-v4.pbrt", 32, 32); }
TEST(RenderScenes, CornellBoxPointLights) {
    expect_renders("cornell-box/scene-pointlights-4096.pbrt", 32, 32);
}
TEST(RenderScenes, VeachMis) { expect_renders("veach-mis/scene-v4.pbrt", 64, 36); }
TEST(RenderScenes, VeachBidir) { expect_renders("veach-bidir/scene-v4.pbrt", 32, 32); }
TEST(RenderScenes, Kitchen) { expect_renders("kitchen/scene-v4.pbrt", 64, 36); }
TEST(RenderScenes, Classroom) { expect_renders("classroom/scene-v4.pbrt", 64, 36); }
TEST(RenderScenes, Coffee) { expect_renders("coffee/scene-v4.pbrt", 32, 40); }
