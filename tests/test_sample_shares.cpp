// Adaptive sampling's shares (manylight/sample_shares.h): a pixel's share of the samples follows
// its neighbours' noise and never its own, averages 1 over the film, and stays within the clamps.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "camera/camera.h"
#include "core/rng.h"
#include "film/film.h"
#include "film/filter.h"
#include "manylight/sample_shares.h"
#include "scene/default_scene.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"

using namespace ml;

namespace {

constexpr int kW = 24, kH = 20;

std::vector<float> random_variance(uint64_t seed, float lo, float hi) {
    Rng rng(seed);
    std::vector<float> v(size_t(kW) * kH);
    for (float& x : v) x = lo + (hi - lo) * rng.next_float();
    return v;
}

float at(const std::vector<float>& s, int x, int y) { return s[size_t(y) * kW + size_t(x)]; }

}  // namespace

TEST(SampleShares, EvenNoiseGivesEveryPixelOne) {
    for (float s : neighbour_sample_shares(kW, kH, std::vector<float>(size_t(kW) * kH, 0.3f)))
        EXPECT_NEAR(s, 1.f, 1e-5f);
    // No noise anywhere, or a variance per pixel missing: an even split.
    for (float s : neighbour_sample_shares(kW, kH, std::vector<float>(size_t(kW) * kH, 0.f)))
        EXPECT_EQ(s, 1.f);
    for (float s : neighbour_sample_shares(kW, kH, std::vector<float>(7, 1.f))) EXPECT_EQ(s, 1.f);
    EXPECT_TRUE(neighbour_sample_shares(0, 5, {}).empty());
}

TEST(SampleShares, APixelsOwnNoiseDoesNotMoveItsShare) {
    // Pixel (10, 10) with a spike, or without: its share against a pixel far from it (beyond
    // kShareRadius of it, so with the same neighbours) is the same. A share taken from the
    // pixel's own noise would grow with the spike.
    std::vector<float> quiet = random_variance(3, 0.5f, 1.5f), spike = quiet;
    spike[size_t(10) * kW + 10] = 1000.f;
    auto a = neighbour_sample_shares(kW, kH, quiet), b = neighbour_sample_shares(kW, kH, spike);
    EXPECT_NEAR(at(a, 10, 10) / at(a, 0, 0), at(b, 10, 10) / at(b, 0, 0), 1e-5f);
    // Its neighbours do take more: the spike says where the noise is.
    EXPECT_GT(at(b, 11, 10) / at(b, 0, 0), 2 * at(a, 11, 10) / at(a, 0, 0));
    EXPECT_NEAR(at(b, 11 + kShareRadius, 10) / at(b, 0, 0),
                at(a, 11 + kShareRadius, 10) / at(a, 0, 0), 1e-5f);
}

TEST(SampleShares, ANoisyRegionTakesSamplesInProportionToItsDeviation) {
    // The left half 16 times as noisy as the right: away from the border between them, the
    // shares' ratio is sqrt(16) = 4, and they average 1.
    std::vector<float> v(size_t(kW) * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) v[size_t(y) * kW + size_t(x)] = x < kW / 2 ? 1.6f : 0.1f;
    auto s = neighbour_sample_shares(kW, kH, v);
    EXPECT_NEAR(at(s, 2, 10) / at(s, kW - 3, 10), 4.f, 1e-4f);
    EXPECT_NEAR(std::accumulate(s.begin(), s.end(), 0.0) / double(s.size()), 1.0, 1e-5);
}

TEST(SampleShares, SharesAverageOneWithinTheClamps) {
    // Noise over six orders of magnitude: the shares are clamped to [kMinSampleShare,
    // kMaxSampleShare] of the mean, then scaled to average 1.
    Rng rng(7);
    std::vector<float> v(size_t(kW) * kH);
    for (float& x : v) x = std::pow(10.f, 6 * rng.next_float() - 3);
    auto s = neighbour_sample_shares(kW, kH, v);
    EXPECT_NEAR(std::accumulate(s.begin(), s.end(), 0.0) / double(s.size()), 1.0, 1e-5);
    auto [lo, hi] = std::minmax_element(s.begin(), s.end());
    EXPECT_LE(*hi / *lo, kMaxSampleShare / kMinSampleShare * (1 + 1e-5f));
    EXPECT_GT(*hi / *lo, 2.f);
    // Non-finite or negative variances count as 0.
    v[5] = NAN, v[6] = -1.f, v[7] = INFINITY;
    for (float x : neighbour_sample_shares(kW, kH, v)) EXPECT_TRUE(std::isfinite(x) && x > 0);
}

TEST(SampleShares, AdaptivePassesKeepEveryPixelsMean) {
    // A stand-in estimator of rare spikes (a sample is 100 with probability 1%, else 0: mean 1,
    // as a glossy highlight's rare hits), its numbers hashed from the pixel and the sample index.
    // Adaptive passes (a first pass of 8 samples, then 4 by the shares) keep the film's mean at
    // 1. A share from the pixel's own first pass (a spike there: a high share that dilutes it)
    // would make it about 0.7. The left half has spikes, the right half none: the shares move
    // samples left, and every pixel's samples are numbered without a gap or a repeat.
    Scene scene(parse_scene_string(default_scene_text(), "."));
    const int w = 32, h = 32, n = 8, spp = 40;
    PerspectiveCamera camera(ParameterList{}, AnimatedTransform(Transform()), w, h);
    auto filter = create_filter("box", ParameterList{}, FileLoc{});
    auto sampler = create_sampler("independent", 1, 1);
    double mean = 0, left = 0;
    int64_t left_samples = 0, right_samples = 0;
    const int films = 40;
    float max_share = 0;
    for (int f = 0; f < films; ++f) {
        Film film(w, h);
        RenderContext ctx{scene, camera, *filter, film, *sampler, spp, 0.0};
        std::vector<int> taken(size_t(w) * h, 0);
        render_adaptive_passes(
            ctx, n, 0.0,
            [&](Point2i p, int first, int samples) {
                const size_t i = size_t(p.y) * w + size_t(p.x);
                EXPECT_EQ(first, taken[i]) << "pixel " << p.x << " " << p.y;
                taken[i] += samples;
                (p.x < w / 2 ? left_samples : right_samples) += samples;
                double sum = 0, sum2 = 0;
                for (int s = first; s < first + samples; ++s) {
                    // (A hash: PCG streams of neighbouring sequence indices are correlated.)
                    const float u = float(hash_ints(uint64_t(f), i, uint64_t(s)) >> 40) * 0x1p-24f;
                    const double x = p.x < w / 2 && u < 0.01f ? 100.0 : 0.0;
                    sum += x, sum2 += x * x;
                }
                const double m = sum / samples;
                film.add_sample(p, RGB(float(m)), float(samples));
                const float var = float((sum2 / samples - m * m) / samples);
                return relative_variance(var, float(m));
            },
            {}, &max_share);
        Image img = film.to_image();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w / 2; ++x) left += img.pixels[size_t(y) * w + size_t(x)][0];
        for (const RGB& p : img.pixels) mean += p[0];
    }
    left /= double(films) * (w / 2) * h;
    // 40 films x 512 pixels x about 70 samples: the mean of the spikes' pixels has a standard
    // error of about 10 / sqrt(1.4e6) = 0.0084.
    EXPECT_NEAR(left, 1.0, 5 * 0.0084);
    EXPECT_NEAR(mean / (double(films) * w * h), 0.5, 5 * 0.0042);
    EXPECT_GT(left_samples, 2 * right_samples) << "the shares do not follow the noise";
    EXPECT_GT(max_share, 1.5f);
}
