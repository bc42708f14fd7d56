// The path tracer against independent renders of the shared Cornell box: Tungsten's RGB
// reference and pbrt-v4's spectral one (../shared/references). The 512 spp figures
// live in bench/; here 64 spp already puts block noise well under the tolerances.
#include <gtest/gtest.h>

#include "film/image_metrics.h"
#include "render_helpers.h"

using namespace ml;

namespace {

const std::string kShared = MANYLIGHT_SHARED_DIR;

Image render_cornell(int spp) {
    RenderOptions opt;
    opt.integrator = "path";
    opt.spp = spp;
    opt.max_depth = 16;
    opt.width = 256;
    opt.height = 256;
    opt.seed = 1;
    opt.progress = false;
    return render_scene(parse_scene_file(kShared + "/scenes/cornell-box/scene-v4.pbrt"), opt).image;
}

}  // namespace

TEST(RenderReference, CornellBoxMatchesTungstenAndPbrt) {
    Image ours = render_cornell(64);
    Image tungsten =
        box_downsample(read_image(kShared + "/scenes/cornell-box/TungstenRender.exr"), 4);
    Image pbrt = read_image(kShared + "/references/cornell-box-path-256-2048spp.exr");

    ImageDiff dt = compare_images(ours, tungsten);
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(dt.mean_rel_diff[c]), 0.02) << "channel " << c;
    double block_t = max_block_rel_diff(ours, tungsten, 16, 0.01f);
    EXPECT_LT(block_t, 0.06);

    ImageDiff dp = compare_images(ours, pbrt);
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(dp.mean_rel_diff[c]), 0.05) << "channel " << c;
    double block_p = max_block_rel_diff(ours, pbrt, 16, 0.01f);
    EXPECT_LT(block_p, 0.12);
    std::printf("vs Tungsten: mean %+.2f%% %+.2f%% %+.2f%%, worst 16x16 block %.2f%%\n",
                100 * dt.mean_rel_diff.r, 100 * dt.mean_rel_diff.g, 100 * dt.mean_rel_diff.b,
                100 * block_t);
    std::printf("vs pbrt-v4:  mean %+.2f%% %+.2f%% %+.2f%%, worst 16x16 block %.2f%%\n",
                100 * dp.mean_rel_diff.r, 100 * dp.mean_rel_diff.g, 100 * dp.mean_rel_diff.b,
                100 * block_p);
}
