#include "integrators/bias_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.h"
#include "core/rng.h"
#include "film/film.h"
#include "integrators/path/path.h"
#include "render/render_loop.h"
#include "sampling/samplers.h"

namespace ml {

namespace {

// Seeds of the check's own random choices, apart from everything the render draws.
constexpr uint64_t kPixelsSeedTag = 0x62696173706978ULL;   // "biaspix"
constexpr uint64_t kSamplesSeedTag = 0x62696173737070ULL;  // "biasspp"
// Judged: an interval wholly outside [1 - kTolerance, 1 + kTolerance] at kVerdictLevel.
constexpr double kTolerance = 0.01;
constexpr double kVerdictLevel = 0.99;
// The most path samples per check pixel the share rule gives without a time limit.
constexpr int kMostSpp = 1 << 20;

// The standard normal quantile: Phi(z) = p, by bisection on erfc (p in (0, 1)).
double normal_quantile(double p) {
    double lo = -40, hi = 40;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

const char* channel_name(int c) { return c == 0 ? "r" : (c == 1 ? "g" : "b"); }

nlohmann::json interval_json(const std::optional<RatioInterval>& i) {
    return i ? nlohmann::json::array({i->lo, i->hi}) : nlohmann::json(nullptr);
}

}  // namespace

BiasCheckMode parse_bias_check_mode(const std::string& s) {
    if (s == "auto") return BiasCheckMode::Auto;
    if (s == "on") return BiasCheckMode::On;
    if (s == "off") return BiasCheckMode::Off;
    throw UsageError("--bias-check: expected auto, on or off, got \"" + s + "\"");
}

void validate(const BiasCheckOptions& o) {
    if (!(o.share > 0 && o.share <= 0.5))
        throw UsageError(
            fmt::format("--bias-check-share: expected a share of the time in (0, 0.5], "
                        "got {}",
                        o.share));
    if (o.pixels < 2)
        throw UsageError(
            fmt::format("--bias-check-pixels: expected at least 2 pixels, got {}", o.pixels));
    if (o.spp && *o.spp < 1)
        throw UsageError(
            fmt::format("--bias-check-spp: expected a positive integer, got {}", *o.spp));
}

bool bias_check_by_default(const std::string& integrator) {
    for (const char* name : {"vpl", "lightcuts", "mdlightcuts", "bdlightcuts",
                             "stochasticlightcuts", "igi", "manylight"})
        if (integrator == name) return true;
    return false;
}

bool bias_check_enabled(const BiasCheckOptions& options, const std::string& integrator) {
    switch (options.mode) {
        case BiasCheckMode::On:
            return true;
        case BiasCheckMode::Off:
            return false;
        case BiasCheckMode::Auto:
            return bias_check_by_default(integrator);
    }
    return false;
}

double student_t_quantile(double level, double df) {
    // Abramowitz and Stegun 26.7.5: t from the normal quantile z in powers of 1 / df.
    const double z = normal_quantile(0.5 + 0.5 * level), z2 = z * z;
    const double g1 = (z2 + 1) * z / 4, g2 = ((5 * z2 + 16) * z2 + 3) * z / 96,
                 g3 = (((3 * z2 + 19) * z2 + 17) * z2 - 15) * z / 384,
                 g4 = ((((79 * z2 + 776) * z2 + 1482) * z2 - 1920) * z2 - 945) * z / 92160;
    return z + (g1 + (g2 + (g3 + g4 / df) / df) / df) / df;
}

std::optional<RatioInterval> ratio_of_means(const std::vector<double>& image,
                                            const std::vector<double>& reference, double level) {
    const size_t n = std::min(image.size(), reference.size());
    if (n < 2) return std::nullopt;
    double sum_i = 0, sum_p = 0;
    for (size_t k = 0; k < n; ++k) sum_i += image[k], sum_p += reference[k];
    if (!(sum_p > 0) || !std::isfinite(sum_i) || !std::isfinite(sum_p)) return std::nullopt;
    // The ratio estimator's residuals d = I - R P: their spread is the ratio's (delta method).
    const double r = sum_i / sum_p, mean_p = sum_p / double(n);
    double ss = 0;
    for (size_t k = 0; k < n; ++k)
        ss += (image[k] - r * reference[k]) * (image[k] - r * reference[k]);
    const double se = std::sqrt(ss / double(n - 1) / double(n)) / mean_p;
    const double t = student_t_quantile(level, double(n - 1));
    return RatioInterval{r, r - t * se, r + t * se};
}

int bias_check_spp(const BiasCheckOptions& options, int render_spp, int width, int height) {
    if (options.spp) return *options.spp;
    const int n = std::min<int64_t>(options.pixels, int64_t(width) * height);
    const double samples = options.share / (1 - options.share) * double(std::max(render_spp, 1)) *
                           double(width) * double(height) / double(std::max(n, 1));
    return int(std::clamp(std::ceil(samples), 1.0, double(kMostSpp)));
}

BiasCheckResult run_bias_check(const BiasCheckInput& in, const BiasCheckOptions& options) {
    auto t0 = std::chrono::steady_clock::now();
    BiasCheckResult result;
    result.ran = true;
    result.max_depth = in.max_depth;
    const int width = in.image.width, height = in.image.height;
    const uint32_t all = uint32_t(int64_t(width) * height);
    const int n = int(std::min<int64_t>(options.pixels, all));

    // 1. The pixels: a seeded permutation's first n, distinct and uniform.
    std::vector<Point2i> pixels(static_cast<size_t>(n));
    const uint64_t pixel_seed = hash_ints(in.seed, kPixelsSeedTag);
    for (int i = 0; i < n; ++i) {
        uint32_t p = sampling_detail::permutation_element(uint32_t(i), all, pixel_seed);
        pixels[size_t(i)] = Point2i{int(p % uint32_t(width)), int(p / uint32_t(width))};
    }

    // 2. Path estimates, one film pixel per check pixel (the film's clamp and scale are the
    // image's), in rounds that run_rounds plans under the time limit.
    Film film(n, 1, in.max_component, in.imaging_ratio);
    const bool timed = in.time_limit > 0;
    const int64_t cap = timed ? (options.spp ? *options.spp : kMostSpp) : std::max(in.spp, 1);
    // Owen-scrambled Sobol': each pixel's estimate is unbiased and, its scramble hashed from the
    // pixel, independent of the others' (all the interval needs), with less noise and a lighter
    // tail than independent samples: a path estimate that misses its rare large samples makes
    // the ratio high with too narrow an interval.
    auto sampler = make_sobol_sampler(int(cap), hash_ints(in.seed, kSamplesSeedTag));
    PathIntegrator path(
        Settings("path", nullptr, {{"path.maxdepth", std::to_string(in.max_depth)}}));
    path.prepare(in.scene);
    RenderContext ctx{in.scene, in.camera,     in.filter, film,   *sampler,
                      int(cap), in.time_limit, nullptr,   in.seed};
    ctx.start = in.start;
    ctx.cancel = in.cancel;
    struct ThreadState {
        std::unique_ptr<Sampler> sampler;
        ScratchBuffer scratch;
    };
    ThreadLocal<ThreadState> states([&] { return ThreadState{sampler->clone(), ScratchBuffer()}; });
    std::vector<int64_t> taken(static_cast<size_t>(n), 0);
    RoundPlan plan;
    plan.total = cap;
    run_rounds(ctx, plan, [&](int64_t s0, int64_t units) {
        const int64_t s1 = std::min(cap, s0 + units);
        std::atomic<bool> cut_short{false};
        // A pixel's samples in index order on one thread. Past the time limit no pixel starts;
        // the pixels done keep their samples (which pixels those are depends on time, not on
        // their values, so the estimate stays unbiased) and the loop ends.
        parallel_for(size_t(0), size_t(n), [&](size_t i) {
            if (ctx.out_of_time()) {
                cut_short = true;
                return;
            }
            ThreadState& ts = states.local();
            for (int64_t s = s0; s < s1; ++s) {
                ts.sampler->start_pixel_sample(pixels[i], int(s));
                float weight, camera_weight;
                Ray ray = pixel_sample_ray(ctx, pixels[i], *ts.sampler, &weight, &camera_weight);
                RGB L =
                    camera_weight > 0
                        ? path.li(ray, in.scene, *ts.sampler, ts.scratch, pixels[i]) * camera_weight
                        : RGB();
                film.add_sample(Point2i{int(i), 0}, L, weight);
                ts.scratch.reset();
            }
            taken[i] += s1 - s0;
        });
        return cut_short ? int64_t(0) : s1 - s0;
    });

    // 3. The intervals, over the pixels path reached.
    Image estimates = film.to_image();
    std::array<std::vector<double>, 3> image, reference;
    for (int i = 0; i < n; ++i) {
        if (taken[size_t(i)] == 0) continue;
        ++result.pixels;
        result.path_samples += taken[size_t(i)];
        for (int c = 0; c < 3; ++c) {
            image[size_t(c)].push_back(in.image.at(pixels[size_t(i)].x, pixels[size_t(i)].y)[c]);
            reference[size_t(c)].push_back(estimates.pixels[size_t(i)][c]);
        }
    }
    // 4. The verdict.
    bool judged = false, off = false;
    for (int c = 0; c < 3; ++c) {
        result.ci95[size_t(c)] = ratio_of_means(image[size_t(c)], reference[size_t(c)], 0.95);
        const auto& ci = result.ci99[size_t(c)] =
            ratio_of_means(image[size_t(c)], reference[size_t(c)], kVerdictLevel);
        if (!ci) continue;
        judged = true;
        off = off || ci->hi < 1 - kTolerance || ci->lo > 1 + kTolerance;
    }
    result.verdict = !judged ? "none" : (off ? "off" : "ok");
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

nlohmann::json BiasCheckResult::to_json() const {
    nlohmann::json ratio = nlohmann::json::array(), ci95_j = nlohmann::json::array(),
                   ci99_j = nlohmann::json::array();
    for (int c = 0; c < 3; ++c) {
        const auto& i = ci99[size_t(c)];
        ratio.push_back(i ? nlohmann::json(i->ratio) : nlohmann::json(nullptr));
        ci95_j.push_back(interval_json(ci95[size_t(c)]));
        ci99_j.push_back(interval_json(i));
    }
    return {{"pixels", pixels},       {"path_spp", path_spp()},  {"path_samples", path_samples},
            {"max_depth", max_depth}, {"ratio", ratio},          {"ci95", ci95_j},
            {"ci99", ci99_j},         {"tolerance", kTolerance}, {"verdict_level", kVerdictLevel},
            {"seconds", seconds},     {"verdict", verdict}};
}

std::string BiasCheckResult::summary() const {
    std::string s = "bias check: image / path";
    for (int c = 0; c < 3; ++c) {
        const auto& i = ci99[size_t(c)];
        s += i ? fmt::format(" {} {:.3f} [{:.3f}, {:.3f}]", channel_name(c), i->ratio, i->lo, i->hi)
               : fmt::format(" {} -", channel_name(c));
    }
    return s + fmt::format(" (99%, {} px x {:.1f} spp, {:.2f} s): {}", pixels, path_spp(), seconds,
                           verdict);
}

std::string BiasCheckResult::warning() const {
    if (verdict != "off") return {};
    std::string ratios;
    for (int c = 0; c < 3; ++c) {
        const auto& i = ci99[size_t(c)];
        if (!i) continue;
        ratios += fmt::format("{}{} {:.3f} [{:.3f}, {:.3f}]", ratios.empty() ? "" : ", ",
                              channel_name(c), i->ratio, i->lo, i->hi);
    }
    return fmt::format(
        "bias check: the image's mean over {} random pixels is off from path's beyond noise and "
        "the {:.0f}% tolerance (image / path with 99% intervals: {}); a setting keeps a bias "
        "(a clamp, diffuse-only glossy VPLs, a cut rule)",
        pixels, kTolerance * 100, ratios);
}

}  // namespace ml
