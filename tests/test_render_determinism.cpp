// Same seed and thread count give bit-identical images; so do different thread counts, since
// every pixel's samples are taken in order by one thread.
#include <gtest/gtest.h>

#include "render_helpers.h"
#include "scene/default_scene.h"

using namespace ml;

namespace {

Image render_default(int threads, uint64_t seed) {
    RenderOptions opt;
    opt.spp = 4;
    opt.width = 48;
    opt.height = 48;
    opt.threads = threads;
    opt.seed = seed;
    return test::render_text(default_scene_text(), opt).image;
}

bool identical(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return false;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        if (!(a.pixels[i] == b.pixels[i])) return false;
    return true;
}

}  // namespace

TEST(RenderDeterminism, SameSeedSameThreadsIsBitIdentical) {
    EXPECT_TRUE(identical(render_default(2, 3), render_default(2, 3)));
}

TEST(RenderDeterminism, ThreadCountDoesNotChangeTheImage) {
    EXPECT_TRUE(identical(render_default(1, 3), render_default(2, 3)));
}

TEST(RenderDeterminism, AnotherSeedChangesTheImage) {
    EXPECT_FALSE(identical(render_default(2, 3), render_default(2, 4)));
}
