// Samplers: range, determinism, stratification ((0,2)-nets for Sobol'), decorrelation and
// convergence.
#include <gtest/gtest.h>

#include <set>

#include "core/error.h"
#include "sampling/samplers.h"

namespace ml {
namespace {

const char* kNames[] = {"independent", "stratified", "sobol"};

std::vector<float> draw(Sampler& s, Point2i px, int index, int dims) {
    s.start_pixel_sample(px, index);
    std::vector<float> v;
    Vec2 p = s.get_pixel_2d();
    v.push_back(p.x);
    v.push_back(p.y);
    for (int d = 0; d < dims; ++d) {
        if (d % 3 == 0) {
            v.push_back(s.get_1d());
        } else {
            Vec2 q = s.get_2d();
            v.push_back(q.x);
            v.push_back(q.y);
        }
    }
    return v;
}

TEST(Sampler, ValuesInRangeAndMeanHalf) {
    for (const char* name : kNames) {
        auto s = create_sampler(name, 16, 1);
        double sum = 0;
        int n = 0;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                for (int i = 0; i < s->samples_per_pixel(); ++i)
                    for (float v : draw(*s, {x, y}, i, 10)) {
                        ASSERT_TRUE(v >= 0.f && v < 1.f) << name;
                        sum += v;
                        ++n;
                    }
        EXPECT_NEAR(sum / n, 0.5, 0.01) << name;
    }
}

TEST(Sampler, DeterministicRegardlessOfOrderAndClones) {
    for (const char* name : kNames) {
        auto a = create_sampler(name, 16, 42);
        auto b = a->clone();
        std::vector<std::vector<float>> forward;
        for (int i = 0; i < 16; ++i) forward.push_back(draw(*a, {3, 5}, i, 12));
        // Reverse order, other pixels in between, on the clone.
        for (int i = 15; i >= 0; --i) {
            draw(*b, {i, 7}, i, 3);
            EXPECT_EQ(draw(*b, {3, 5}, i, 12), forward[size_t(i)]) << name;
        }
        // Starting at a dimension offset equals skipping those dimensions.
        a->start_pixel_sample({3, 5}, 2, 4);
        float skipped = a->get_1d();
        a->start_pixel_sample({3, 5}, 2, 0);
        for (int d = 0; d < 4; ++d) a->get_1d();
        EXPECT_EQ(a->get_1d(), skipped) << name;
        // Another seed or pixel differs.
        auto c = create_sampler(name, 16, 43);
        EXPECT_NE(draw(*c, {3, 5}, 0, 12), forward[0]) << name;
        EXPECT_NE(draw(*a, {4, 5}, 0, 12), forward[0]) << name;
        EXPECT_EQ(a->name(), b->name());
    }
}

TEST(Sampler, StratifiedAndSobolStratifyFirstDimension) {
    for (const char* name : {"stratified", "sobol"}) {
        for (int spp : {4, 16, 64}) {
            auto s = create_sampler(name, spp, 7);
            ASSERT_EQ(s->samples_per_pixel(), spp);
            for (int px = 0; px < 4; ++px) {
                // Every 1D dimension of the pixel has one sample per 1/spp stratum.
                for (int dim = 0; dim < 5; ++dim) {
                    std::set<int> strata;
                    for (int i = 0; i < spp; ++i) {
                        s->start_pixel_sample({px, 1}, i, dim);
                        strata.insert(int(s->get_1d() * spp));
                    }
                    EXPECT_EQ(int(strata.size()), spp) << name << " spp " << spp << " dim " << dim;
                }
            }
        }
    }
}

TEST(Sampler, SobolPairsAreZeroTwoNets) {
    for (int log2n : {2, 4, 6, 8}) {
        int n = 1 << log2n;
        auto s = create_sampler("sobol", n, 3);
        for (int dim : {0, 2, 6}) {
            std::vector<Vec2> pts;
            for (int i = 0; i < n; ++i) {
                s->start_pixel_sample({5, 9}, i, dim);
                pts.push_back(s->get_2d());
            }
            // Every elementary interval of shape 2^-a x 2^-(m-a) holds exactly one point.
            for (int a = 0; a <= log2n; ++a) {
                int nx = 1 << a, ny = n >> a;
                std::set<int> cells;
                for (Vec2 p : pts) cells.insert(int(p.x * nx) * ny + int(p.y * ny));
                EXPECT_EQ(int(cells.size()), n) << "n " << n << " dim " << dim << " a " << a;
            }
        }
        std::vector<Vec2> pix;
        std::set<int> cells;
        for (int i = 0; i < n; ++i) {
            s->start_pixel_sample({5, 9}, i);
            Vec2 p = s->get_pixel_2d();
            cells.insert(int(p.x * n) * 1 + 0 * int(p.y));
        }
        EXPECT_EQ(int(cells.size()), n);
    }
}

TEST(Sampler, PairsAreDecorrelated) {
    // Dimension pairs of one sample should not repeat each other's values.
    auto s = create_sampler("sobol", 64, 1);
    double cov = 0;
    for (int i = 0; i < 64; ++i) {
        s->start_pixel_sample({0, 0}, i);
        Vec2 a = s->get_2d(), b = s->get_2d();
        cov += (a.x - 0.5) * (b.x - 0.5);
        EXPECT_NE(a.x, b.x);
    }
    EXPECT_LT(std::abs(cov / 64), 0.02);
}

TEST(Sampler, SobolIntegratesSmoothFunctionsBetter) {
    // f(x, y) = x^2 * exp(y), integral (1/3)(e - 1).
    const double exact = (std::exp(1.0) - 1) / 3;
    auto rms = [&](const char* name) {
        const int spp = 256, pixels = 64;
        auto s = create_sampler(name, spp, 11);
        double err2 = 0;
        for (int px = 0; px < pixels; ++px) {
            double sum = 0;
            for (int i = 0; i < spp; ++i) {
                s->start_pixel_sample({px, 0}, i);
                s->get_1d();
                Vec2 u = s->get_2d();
                sum += double(u.x) * u.x * std::exp(double(u.y));
            }
            err2 += sqr(float(sum / spp - exact));
        }
        return std::sqrt(err2 / pixels);
    };
    double e_ind = rms("independent"), e_sobol = rms("sobol"), e_strat = rms("stratified");
    EXPECT_LT(e_sobol, e_ind / 10) << e_sobol << " vs " << e_ind;
    EXPECT_LT(e_strat, e_ind / 3) << e_strat << " vs " << e_ind;
}

TEST(Sampler, FactoryNames) {
    EXPECT_THROW(create_sampler("halton-ish", 4, 0), UsageError);
    EXPECT_EQ(create_sampler("stratified", 8, 0)->samples_per_pixel(), 9);
    EXPECT_EQ(make_stratified_sampler(4, 2, true, 0)->samples_per_pixel(), 8);
}

}  // namespace
}  // namespace ml
