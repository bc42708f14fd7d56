// Splats through the pixel filter (SplatFilter, pbrt-v4's RGBFilm::AddSplat): a splat's weights
// are the filter's values at the pixel centres over its integral, so over uniformly placed splats
// each pixel receives on average what a camera sample drawn from the filter would give it; a
// pixel-sized box puts everything in the pixel that holds the splat; values are clamped first.
#include <gtest/gtest.h>

#include <vector>

#include "core/rng.h"
#include "film/filter.h"
#include "film/splat_filter.h"

using namespace ml;

namespace {

std::unique_ptr<Filter> make_filter(const std::string& name) {
    ParameterList p;
    return create_filter(name, p, {});
}

// The integral of eval, by the midpoint rule on a fine grid.
double numeric_integral(const Filter& f) {
    Vec2 r = f.radius();
    const int n = 600;
    double s = 0, dx = 2 * r.x / n, dy = 2 * r.y / n;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            s += f.eval(Vec2(float(-r.x + (i + 0.5) * dx), float(-r.y + (j + 0.5) * dy)));
    return s * dx * dy;
}

}  // namespace

TEST(SplatFilter, IntegralsMatchTheFilters) {
    for (const char* name : {"box", "triangle", "gaussian"}) {
        auto f = make_filter(name);
        EXPECT_NEAR(f->integral(), numeric_integral(*f), 2e-3 * f->integral()) << name;
    }
}

// Splats uniform over a pixel's neighbourhood: the mean total weight a pixel receives per unit
// area of splat positions is one (the filter over its integral, integrated), for every filter.
TEST(SplatFilter, UniformSplatsGiveEachPixelUnitWeight) {
    for (const char* name : {"box", "triangle", "gaussian"}) {
        auto f = make_filter(name);
        SplatFilter spread(*f, 9, 9, kInfinity);
        Rng rng(17);
        const int n = 400000;
        double centre = 0, total = 0;
        for (int i = 0; i < n; ++i) {
            // Uniform over [2, 7)^2: the centre pixel (4, 4)'s whole footprint (radius <= 2).
            Vec2 p(2 + 5 * rng.next_float(), 2 + 5 * rng.next_float());
            spread.spread(p, RGB(1.f), [&](size_t pixel, const RGB& v) {
                if (pixel == 4 * 9 + 4) centre += v.g;
                total += v.g;
            });
        }
        // The centre pixel's footprint lies inside the square: mean weight * area = 1.
        EXPECT_NEAR(centre * 25 / n, 1.0, 0.01) << name;
        EXPECT_GT(total / n, 0.9) << name;
    }
}

TEST(SplatFilter, PixelSizedBoxFillsThePixelThatHoldsTheSplat) {
    auto f = make_filter("box");
    SplatFilter spread(*f, 8, 4, kInfinity);
    Rng rng(3);
    for (int i = 0; i < 1000; ++i) {
        Vec2 p(8 * rng.next_float(), 4 * rng.next_float());
        int count = 0;
        spread.spread(p, RGB(2.f, 3.f, 4.f), [&](size_t pixel, const RGB& v) {
            ++count;
            EXPECT_EQ(pixel, size_t(std::floor(p.y)) * 8 + size_t(std::floor(p.x)));
            EXPECT_FLOAT_EQ(v.b, 4.f);
        });
        EXPECT_EQ(count, 1);  // (exactly on a pixel edge, probability zero, it would reach two)
    }
}

TEST(SplatFilter, ClampsToTheMaximumComponentAndDropsNonFinite) {
    auto f = make_filter("gaussian");
    SplatFilter spread(*f, 16, 16, 10.f);
    // Scaled by 10 / 40 like a camera sample, then spread as the scaled value is.
    std::vector<RGB> clamped, scaled;
    spread.spread(Vec2(8.3f, 7.6f), RGB(40.f, 20.f, 4.f),
                  [&](size_t, const RGB& v) { clamped.push_back(v); });
    spread.spread(Vec2(8.3f, 7.6f), RGB(10.f, 5.f, 1.f),
                  [&](size_t, const RGB& v) { scaled.push_back(v); });
    ASSERT_EQ(clamped.size(), scaled.size());
    ASSERT_GE(clamped.size(), 4u);
    for (size_t i = 0; i < clamped.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(clamped[i][c], scaled[i][c]);
    int calls = 0;
    spread.spread(Vec2(8, 8), RGB(std::nanf(""), 1.f, 1.f), [&](size_t, const RGB&) { ++calls; });
    EXPECT_EQ(calls, 0);
}
