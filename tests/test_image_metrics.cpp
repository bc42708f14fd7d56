// Block comparisons of images (film/image_metrics.h): whole blocks only, at any image size.
#include <gtest/gtest.h>

#include "core/error.h"
#include "film/image_metrics.h"

namespace ml {

TEST(ImageMetrics, WorstBlocksTakeWholeBlocksOfAnyImageSize) {
    // 20x18 with 8x8 blocks: 2x2 whole blocks; the last 4 columns and 2 rows are in none.
    Image ref(20, 18), a(20, 18);
    for (RGB& p : ref.pixels) p = RGB(1.f);
    a = ref;
    for (int y = 0; y < 18; ++y)
        for (int x = 16; x < 20; ++x) a.at(x, y) = RGB(5.f);  // outside every whole block
    for (int x = 0; x < 20; ++x) a.at(x, 17) = RGB(5.f);
    EXPECT_EQ(max_block_rel_diff(a, ref, 8), 0.0);
    // One pixel of block (1, 1) doubled in green: that block's green mean is 1 + 1/64.
    a.at(9, 9).g = 2.f;
    std::vector<BlockDiff> w = worst_blocks(a, ref, 8, 10);
    ASSERT_EQ(w.size(), 10u);
    EXPECT_EQ(w[0].x, 1);
    EXPECT_EQ(w[0].y, 1);
    EXPECT_EQ(w[0].channel, 1);
    EXPECT_NEAR(w[0].rel(), 1.0 / 64, 1e-6);
    EXPECT_EQ(worst_blocks(a, ref, 8, 100).size(), 12u);  // 4 blocks x 3 channels
    EXPECT_THROW(worst_blocks(a, Image(8, 8), 8, 1), Error);
}

}  // namespace ml
