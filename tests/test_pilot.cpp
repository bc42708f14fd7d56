// The pilot of the cuts' error floor (manylight/pilot.h): a grid of about kPilotPixels pixels,
// evenly over the film, whose mean it returns the same way whatever the schedule.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "manylight/pilot.h"

namespace ml {

TEST(Pilot, MeanOfALinearImageIsItsMean) {
    // Luminance of RGB(v) is v: a ramp in x and y has mean (w - 1) / 2 + (h - 1) / 2 over the
    // film, and the grid's cells' middles sample it evenly (within a cell's width).
    for (auto [w, h] : {std::pair{320, 180}, std::pair{17, 5}, std::pair{1000, 3}}) {
        std::atomic<int> calls{0};
        double mean = pilot_mean_luminance(w, h, [&](Point2i p) {
            ++calls;
            EXPECT_TRUE(p.x >= 0 && p.x < w && p.y >= 0 && p.y < h);
            return RGB(float(p.x + p.y));
        });
        double expected = (w - 1) / 2.0 + (h - 1) / 2.0;
        int step = std::max(1, int(std::lround(std::sqrt(double(w) * h / kPilotPixels))));
        EXPECT_NEAR(mean, expected, step) << w << "x" << h;
        EXPECT_LE(calls.load(), std::max(w * h, 2 * kPilotPixels));
        EXPECT_GE(calls.load(), std::min(w * h, kPilotPixels / 2));
    }
}

TEST(Pilot, NegativeAndNonFiniteValuesCountAsZero) {
    double mean = pilot_mean_luminance(4, 4, [](Point2i p) {
        if (p.x == 0) return RGB(-5.f);
        if (p.x == 1) return RGB(std::nanf(""));
        return RGB(2.f);
    });
    EXPECT_DOUBLE_EQ(mean, 1.0);  // half the pixels at 2
    EXPECT_EQ(pilot_mean_luminance(0, 10, [](Point2i) { return RGB(1.f); }), 0.0);
}

}  // namespace ml
