// The pilot of the cuts' error floor (manylight/pilot.h): a grid of about kPilotPixels pixels,
// evenly over the film, whose mean it returns the same way whatever the schedule; and the cut cap
// that a time-limited pass plans from a timing probe.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "camera/camera.h"
#include "film/film.h"
#include "film/filter.h"
#include "manylight/pilot.h"
#include "scene/default_scene.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"

namespace ml {

namespace {

// What render_sample_passes needs around a stand-in pass: the default scene, a 16x16 pinhole
// camera and film, a box filter and an independent sampler.
struct PassStage {
    static constexpr int w = 16, h = 16;
    Scene scene{parse_scene_string(default_scene_text(), ".")};
    PerspectiveCamera camera{ParameterList{}, AnimatedTransform(Transform()), w, h};
    std::unique_ptr<Filter> filter = create_filter("box", ParameterList{}, FileLoc{});
    std::unique_ptr<Sampler> sampler = create_sampler("independent", 1, 1);
    Film film{w, h};
    RenderContext context(int spp, double limit) {
        return RenderContext{scene, camera, *filter, film, *sampler, spp, limit};
    }
};

}  // namespace

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

// choose_cut_cap under a linear time model, every expected cap worked out by hand: a pixel costs
// 1 ms per pair (0 fixed), the film has 1000 pixels.
TEST(CutCap, LargestCapThatFitsTheTime) {
    CutProbe probe;
    probe.low_seconds = 64e-3;  // cap 64: 64 pairs at every pixel
    probe.low_mean_size = 64;
    probe.full_sizes = {100, 900, 100, 900};  // mean 500 at max_cut 1000
    probe.full_seconds = 500e-3;
    // Whole cuts take 1000 * 0.5 = 500 s: a 1000 s budget keeps max_cut.
    CutCapPlan plan = choose_cut_cap(probe, 1000, 64, 1000, 1000);
    EXPECT_EQ(plan.cap, 1000);
    EXPECT_NEAR(plan.full_seconds, 500, 1e-9);
    EXPECT_NEAR(plan.mean_full_size, 500, 1e-9);
    // 300.25 s: a mean of 300 pairs, (min(100, c) + min(900, c)) / 2 = 300 at c = 500.
    plan = choose_cut_cap(probe, 1000, 64, 1000, 300.25);
    EXPECT_EQ(plan.cap, 500);
    EXPECT_NEAR(plan.capped_seconds, 300, 1e-6);
    // 100 s: a mean of 100 pairs, (100 + 100) / 2 at c = 100.
    plan = choose_cut_cap(probe, 1000, 64, 1000, 100);
    EXPECT_EQ(plan.cap, 100);
    EXPECT_EQ(plan.samples_scale, 1);
    EXPECT_EQ(pass_samples(32, plan), 32);
    // 50 s: nothing fits; the least cap (64 s), and the samples scaled by 50 / 64, with the
    // margin: 32 x 0.78125 x 0.8 = 20.
    plan = choose_cut_cap(probe, 1000, 64, 1000, 50);
    EXPECT_EQ(plan.cap, 64);
    EXPECT_NEAR(plan.samples_scale, 0.8 * 50.0 / 64.0, 1e-9);  // no half-samples visit
    EXPECT_EQ(pass_samples(32, plan), 20);
    EXPECT_EQ(pass_samples(1, plan), 1);
}

TEST(CutCap, AFixedCostPerPixelCounts) {
    // Per pixel 10 ms fixed plus 1 ms per pair: cap 64 costs 74 ms, whole cuts (400) 410 ms.
    CutProbe probe;
    probe.low_seconds = 74e-3;
    probe.low_mean_size = 64;
    probe.full_sizes = {400, 400};
    probe.full_seconds = 410e-3;
    // 100 pixels in 20.05 s: 200.5 ms a pixel, 190.5 pairs.
    EXPECT_EQ(choose_cut_cap(probe, 100, 64, 1000, 20.05).cap, 190);
    // Without a figure (the probe ran out of time), the least cap and one sample a pass.
    probe.full_seconds = -1;
    CutCapPlan plan = choose_cut_cap(probe, 100, 64, 1000, 1e9);
    EXPECT_EQ(plan.cap, 64);
    EXPECT_EQ(pass_samples(32, plan), 1);
}

TEST(CutCap, CutsThatOvershootTheirCapCount) {
    // Cuts at cap 64 end at 128 pairs (the cut splits spikes past its cap): a cap c is taken as
    // 2c pairs. 1 ms per pair, no fixed cost, whole cuts of 1000 pairs.
    CutProbe probe;
    probe.low_seconds = 128e-3;
    probe.low_mean_size = 128;
    probe.full_sizes = {1000, 1000};
    probe.full_seconds = 1000e-3;
    // 10 pixels in 4.005 s: 400.5 ms a pixel, 400.5 pairs, 2c <= 400.5 at c = 200.
    CutCapPlan plan = choose_cut_cap(probe, 10, 64, 1000, 4.005);
    EXPECT_EQ(plan.cap, 200);
    EXPECT_NEAR(plan.capped_seconds, 4.0, 1e-6);
}

TEST(CutCap, FewerSamplesWhereTheLeastCutDoesNotFit) {
    // A pixel at cap 64: 64 ms with 32 samples, 40 ms with 16 (so 1.5 ms a sample, 16 ms of
    // cut). 100 pixels in 5.2 s: 52 ms a pixel, (52 - 16) / 1.5 = 24 samples.
    CutProbe probe;
    probe.low_seconds = 64e-3;
    probe.low_mean_size = 64;
    probe.half_seconds = 40e-3;
    probe.full_sizes = {500, 500};
    probe.full_seconds = 500e-3;
    CutCapPlan plan = choose_cut_cap(probe, 100, 64, 1000, 5.2);
    EXPECT_EQ(plan.cap, 64);
    EXPECT_NEAR(plan.samples_scale, 0.75, 1e-9);
    EXPECT_EQ(pass_samples(32, plan), 24);
    // Of the 52 ms of a pixel's pass of 24 samples, the cut's 16 do not shrink with them.
    EXPECT_NEAR(plan.fixed_share, 16.0 / 52.0, 1e-9);
    // Not even the cut alone fits: one sample.
    EXPECT_EQ(pass_samples(32, choose_cut_cap(probe, 100, 64, 1000, 1.0)), 1);
    // The probe visits at half the samples when a pass has 2 or more.
    std::atomic<int> half{0}, calls{0};
    probe = probe_cuts(64, 64, 64, 1000, 8, 1e6, [&](Point2i, int cap, int samples) {
        ++calls;
        if (samples == 4) {
            EXPECT_EQ(cap, 64);
            ++half;
        }
        return cap;
    });
    // Four visits of the same pixels: a warm-up and a timed one at cap 64, whole cuts, half.
    EXPECT_EQ(4 * half.load(), calls.load());
    EXPECT_GT(probe.half_seconds, 0);
}

// The last pass under a time limit: the samples that fill 95% of the time left, at the measured
// pass time split into a fixed part and a part linear in the samples; worked out by hand.
TEST(CutCap, TheLastPassFillsTheTimeLeft) {
    // 8 s a pass of 32 samples, a quarter of it fixed; 3 s left: 2.85 s, 2 s fixed, 0.85 s of
    // samples at 6 s / 32 = 0.1875 s each: 4.53, so 4.
    EXPECT_EQ(remainder_samples(32, 8, 0.25, 3), 4);
    // No fixed part: 32 x 0.95 x 4 / 8 = 15.2.
    EXPECT_EQ(remainder_samples(32, 8, 0, 4), 15);
    // The fixed part alone overruns: none; a pass of one sample cannot shrink; nor can a pass
    // whose cost does not depend on its samples.
    EXPECT_EQ(remainder_samples(32, 8, 0.5, 3), 0);
    EXPECT_EQ(remainder_samples(1, 8, 0, 100), 0);
    EXPECT_EQ(remainder_samples(32, 8, 1, 100), 0);
    EXPECT_EQ(remainder_samples(32, 8, 0, 0), 0);
    // Room for a whole pass: one sample short of it (whole passes are the render loop's).
    EXPECT_EQ(remainder_samples(32, 1, 0, 100), 31);

    // The plan's fixed share at a cap that fits: per pixel 10 ms fixed plus 1 ms a pair, and at
    // cap 64 (74 ms) 20 ms less with half the samples, so 40 ms of samples. 100 pixels in
    // 20.05 s: cap 190 (AFixedCostPerPixelCounts), a pass of 100 x 200 ms = 20 s of which 4 s
    // are samples.
    CutProbe probe;
    probe.low_seconds = 74e-3;
    probe.half_seconds = 54e-3;
    probe.low_mean_size = 64;
    probe.full_sizes = {400, 400};
    probe.full_seconds = 410e-3;
    CutCapPlan plan = choose_cut_cap(probe, 100, 64, 1000, 20.05);
    EXPECT_EQ(plan.cap, 190);
    EXPECT_NEAR(plan.fixed_share, 1 - 4 / 20.0, 1e-6);
    // Whole cuts fit: 41 s a pass.
    plan = choose_cut_cap(probe, 100, 64, 1000, 1e9);
    EXPECT_NEAR(plan.fixed_share, 1 - 4 / 41.0, 1e-6);
    // Without the half-samples visit nothing is known: all fixed.
    probe.half_seconds = -1;
    EXPECT_EQ(choose_cut_cap(probe, 100, 64, 1000, 20.05).fixed_share, 1);
}

// The passes a VPL set serves, worked out by hand: a set of 0.19 s beside passes of 1 s, within
// 5% of them, serves ceil(0.19 / 0.05) = 4; a set within the share, one pass.
TEST(CutCap, AVplSetServesThePassesThatKeepItWithinItsShare) {
    struct Case {
        double set_seconds, pass_seconds, share, mean_cut;
        int passes;
        const char* why;
    };
    const Case cases[] = {
        {0.19, 1.0, 0.05, 1.7, 4, "ceil(0.19 / 0.05)"},
        {0.21, 1.0, 0.05, 8, 5, "ceil(0.21 / 0.05), at the largest small cut"},
        {0.04, 1.0, 0.05, 1.7, 1, "within the share"},
        {0.19, 1.0, 0.05, 9, 1, "large cuts: the VPLs carry much of the image"},
        {0.19, 1.0, 0.05, 150, 1, "cuts at their cap"},
        {0.19, 0, 0.05, 1.7, 1, "no predicted pass (no time limit)"},
        {0.19, 1.0, 0, 1.7, 1, "no share"},
        {0, 1.0, 0.05, 1.7, 1, "a free set"},
        {std::nan(""), 1.0, 0.05, 1.7, 1, "an unmeasured set"},
    };
    for (const Case& c : cases)
        EXPECT_EQ(passes_per_set(c.set_seconds, c.pass_seconds, c.share, c.mean_cut), c.passes)
            << c.why;
}

// render_sample_passes under a time limit, with a stand-in pass whose time is its samples:
// whole passes of 64 samples at consecutive sample indices, then, where the last whole pass left
// room, one pass of fewer samples after them; every pixel alike, and the render ends in time.
TEST(CutCap, RenderSamplePassesEndsWithAPassThatFillsTheTime) {
    PassStage stage;
    const int w = PassStage::w, h = PassStage::h;
    const double limit = 1.0;
    RenderContext ctx = stage.context(1 << 20, limit);
    // Per pixel its passes (first sample, samples), and when the last whole pass ended.
    std::vector<std::vector<std::pair<int, int>>> calls(w * h);
    std::atomic<int64_t> whole_end_us{0};
    const int n = 64;
    SamplePasses done = render_sample_passes(ctx, n, 0.0, [&](Point2i p, int first, int samples) {
        // About 0.6 s a pass of 64 samples on 2 threads (4 tiles of 8x8 pixels).
        std::this_thread::sleep_for(std::chrono::microseconds(73 * samples));
        calls[p.y * w + p.x].push_back({first, samples});
        if (samples == n) {
            int64_t t = int64_t(ctx.elapsed() * 1e6), prev = whole_end_us.load();
            while (t > prev && !whole_end_us.compare_exchange_weak(prev, t)) {
            }
        }
    });
    EXPECT_LT(ctx.elapsed(), limit + 0.3);
    // On a machine so loaded that not even the first pass ended in time, nothing else holds.
    const int64_t total = done.samples, last = done.last_samples;
    if (total == 0) return;
    EXPECT_EQ(total, done.whole * n + last);
    EXPECT_LT(last, n);
    EXPECT_GT(done.pass_seconds, 0);
    for (const auto& pixel : calls) {
        ASSERT_FALSE(pixel.empty());
        for (size_t i = 0; i < pixel.size(); ++i) {
            EXPECT_EQ(pixel[i].first, int(i) * n);
            if (i + 1 < pixel.size()) {
                EXPECT_EQ(pixel[i].second, n);
            }
        }
        // A pixel has the samples that counted, and maybe more from a round the limit cut short.
        int64_t sum = 0;
        for (auto [first, samples] : pixel) sum += samples;
        EXPECT_GE(sum, total);
    }
    // The last whole pass ended with 30% of the time left, more than a pass of 64 samples would
    // fill at what it took: a pass of fewer samples ran, on every pixel unless the limit cut it
    // short.
    if (whole_end_us.load() < 0.7e6 * limit) {
        bool smaller = false;
        for (const auto& pixel : calls) smaller |= pixel.back().second < n;
        EXPECT_TRUE(smaller) << "total " << total;
        if (!ctx.out_of_time()) {
            EXPECT_GT(last, 0);
        }
    }
}

// Where the cuts alone overrun the time left, the last pass is scaled down as a whole: samples
// and cut both to the share phi = 0.95 x time left / pass time; worked out by hand.
TEST(CutCap, ALastPassScaledDownWhereTheCutsAloneOverrun) {
    // Half of an 8 s pass fixed, 3 s left: no pass of fewer samples fits (4 s of cuts); phi =
    // 0.95 x 3 / 8 = 0.35625: 11 of 32 samples, cuts of 0.35625 of the mean.
    LastPass p = last_pass(32, 8, 0.5, 3);
    EXPECT_EQ(p.samples, 11);
    EXPECT_NEAR(p.cut_share, 0.35625, 1e-9);
    // Where fewer samples fit, the cuts stay whole (remainder_samples's 4).
    p = last_pass(32, 8, 0.25, 3);
    EXPECT_EQ(p.samples, 4);
    EXPECT_EQ(p.cut_share, 1);
    // Below kMinLastPassShare of a pass (0.95 x 0.5 / 8 = 0.059): none. A fixed share of 1
    // (nothing measured): none. A pass of one sample keeps it, with smaller cuts.
    EXPECT_EQ(last_pass(32, 8, 0.5, 0.5).samples, 0);
    EXPECT_EQ(last_pass(32, 8, 1, 3).samples, 0);
    p = last_pass(1, 8, 0.5, 3);
    EXPECT_EQ(p.samples, 1);
    EXPECT_NEAR(p.cut_share, 0.35625, 1e-9);
    // Its cap: the share of the whole passes' mean cut, at least kMinLastPassCut, at most theirs.
    EXPECT_EQ(last_pass_cap({11, 0.35625}, 128, 300), 45);
    EXPECT_EQ(last_pass_cap({1, 0.1}, 128, 300), kMinLastPassCut);
    EXPECT_EQ(last_pass_cap({11, 0.9}, 400, 300), 300);
    EXPECT_EQ(last_pass_cap({4, 1}, 128, 300), 300);
}

// render_sample_passes where a pass's cost is almost all fixed (the cuts): the last pass is
// scaled down as a whole, and the integrator hears of it before it runs.
TEST(CutCap, RenderSamplePassesScalesTheLastPassDown) {
    PassStage stage;
    const double limit = 1.0;
    RenderContext ctx = stage.context(1 << 20, limit);
    const int n = 64;
    std::atomic<int> heard{0}, last_calls{0};
    LastPass told;
    // About 0.35 s a pass of 64 samples on 2 threads (4 tiles of 8x8 pixels), what the last
    // pass's smaller cut share shortens.
    double share = 1;
    SamplePasses done = render_sample_passes(
        ctx, n, 0.99,
        [&](Point2i, int, int samples) {
            if (samples < n) ++last_calls;
            std::this_thread::sleep_for(std::chrono::microseconds(int(43 * n * share)));
        },
        [&](const LastPass& plan) {
            ++heard;
            told = plan;
            share = plan.cut_share;
        });
    EXPECT_LT(ctx.elapsed(), limit + 0.3);
    EXPECT_LE(heard.load(), 1);
    if (heard.load() == 0) {
        EXPECT_EQ(last_calls.load(), 0);
        return;
    }
    // The fixed part alone (99%) never fits in less than a whole pass: a scaled pass.
    EXPECT_LT(told.cut_share, 1);
    EXPECT_GE(told.cut_share, kMinLastPassShare);
    EXPECT_GE(told.samples, 1);
    EXPECT_LT(told.samples, n);
    EXPECT_GT(last_calls.load(), 0);
    if (done.last_samples > 0) {
        EXPECT_EQ(done.last_samples, told.samples);
        EXPECT_EQ(done.last_cut_share, told.cut_share);
        EXPECT_EQ(done.samples, done.whole * n + told.samples);
    }
}

// render_sample_passes with `after_first` (adaptive sampling): the whole first pass runs before
// it, once, and every later pass after it, whichever way the rounds group the passes.
TEST(CutCap, AfterFirstRunsBetweenTheFirstPassAndTheOthers) {
    const int w = PassStage::w, h = PassStage::h;
    for (double limit : {0.0, 0.5}) {
        SCOPED_TRACE(limit);
        PassStage stage;
        RenderContext ctx = stage.context(limit > 0 ? 1 << 20 : 40, limit);
        std::atomic<int> first_pass{0}, early{0}, later{0}, after{0};
        SamplePasses done = render_sample_passes(
            ctx, 8, 0.0,
            [&](Point2i, int first, int samples) {
                if (limit > 0) std::this_thread::sleep_for(std::chrono::microseconds(20 * samples));
                if (first == 0) {
                    ++first_pass;
                    if (after.load() > 0) ++early;  // a first pass after the hook
                } else {
                    ++later;
                    if (after.load() == 0) ++early;  // a later pass before it
                }
            },
            {},
            [&] {
                ++after;
                EXPECT_EQ(first_pass.load(), w * h) << "the first pass is not whole";
            });
        EXPECT_EQ(after.load(), 1);
        EXPECT_EQ(early.load(), 0);
        EXPECT_EQ(first_pass.load(), w * h);
        EXPECT_GE(done.whole, 2);
        EXPECT_GE(later.load(), int(done.whole - 1) * w * h);
        if (limit == 0) {
            EXPECT_EQ(done.whole, 5);
            EXPECT_EQ(later.load(), 4 * w * h);
        }
    }
}

TEST(CutCap, TheProbeVisitsAGridAtBothCaps) {
    std::atomic<int> low{0}, full{0};
    CutProbe probe = probe_cuts(320, 180, 64, 1000, 1, 1e6, [&](Point2i p, int cap, int samples) {
        EXPECT_EQ(samples, 1);
        EXPECT_TRUE(p.x >= 0 && p.x < 320 && p.y >= 0 && p.y < 180);
        ++(cap == 64 ? low : full);
        return std::min(cap, 300);
    });
    // At cap 64 a warm-up visit, then the timed one; whole cuts once (a pass of one sample has
    // no half-samples visit).
    EXPECT_GE(full.load(), kCutProbePixels / 2);
    EXPECT_EQ(low.load(), 2 * full.load());
    EXPECT_EQ(probe.full_sizes.size(), size_t(full.load()));
    EXPECT_LT(probe.half_seconds, 0);
    EXPECT_NEAR(probe.low_mean_size, 64, 1e-9);
    EXPECT_GT(probe.full_seconds, 0);
    CutCapPlan plan = choose_cut_cap(probe, 320 * 180, 64, 1000, 1e6);
    EXPECT_EQ(plan.cap, 1000);  // a million seconds is enough
    EXPECT_NEAR(plan.mean_full_size, 300, 1e-9);
    // Where shading a pixel takes longer than the probe's share of the time, each visit stops
    // after the pixels it started.
    std::atomic<int> calls{0};
    probe = probe_cuts(320, 180, 64, 1000, 1, 1e-3, [&](Point2i, int cap, int) {
        ++calls;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        return cap;
    });
    EXPECT_LE(calls.load(), 2 * 16);  // at most a few per thread and visit
    EXPECT_EQ(choose_cut_cap(probe, 320 * 180, 64, 1000, 1e-3).cap, 64);
}

}  // namespace ml
