// The bias check: a render that says how far off it may be. After the main render, the unbiased
// path tracer estimates a few hundred pixels drawn at random from the render's seed, and the
// image's mean over those pixels is compared with the path tracer's, per channel, with a
// confidence interval. An interval that lies wholly outside [0.99, 1.01] means the image's mean
// is off by more than 1%, beyond what noise explains: a bias (a clamp, diffuse-only glossy
// VPLs, a cut rule), which the render then reports as a warning.
//
// Steps:
//   1. Pixels: the first n elements of a pseudo-random permutation of the image's pixels
//      (sampling_detail::permutation_element) seeded by a hash of the render's seed: distinct,
//      uniform, the same for a seed on any thread count.
//   2. Path estimates: `path` (same max depth as the render) takes k samples in each chosen pixel
//      with a Sobol' sampler of its own seed (so the main image is untouched), through the
//      same camera, filter and film clamp as the image; each pixel's samples run in index order
//      on one thread, so the estimates are the same for a seed whatever the thread count.
//   3. Interval: R = sum(I_i) / sum(P_i) over the pixels, per channel (I: the image, P: path).
//      The pairs (I_i, P_i) are independent draws (a random pixel, the image's own noise there,
//      path's noise there), so the ratio estimator's delta-method variance,
//          Var(R) ~ sum (I_i - R P_i)^2 / (n (n - 1) mean(P)^2),
//      holds all three: the noise of both estimates and the spread over pixels (the latter only
//      through how I/P varies, not how bright pixels are). Student-t quantiles with n - 1
//      degrees of freedom. Per-pixel sample variances of P would leave out the image's noise.
//   4. Verdict: "off" when the 99% interval of some channel lies wholly outside [0.99, 1.01],
//      "ok" otherwise. 99%, not 95%: the warning is checked on three channels of every render,
//      so that a correct render warns at most about 1 time in 100 (and much less when the
//      interval is narrow, where the 1% tolerance dominates). --stats has the 95% interval too.
//
// Time: under a time limit the main render gets (1 - share) of it and the check runs until the
// whole limit is spent, in rounds of samples per pixel that grow as the render loop's do
// (run_rounds); without one, k = share / (1 - share) * (the render's path samples) / n: the
// check costs about `share` of the total when a sample of the render costs at least a path.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "film/filter.h"
#include "film/image.h"
#include "scene/scene.h"

namespace ml {

enum class BiasCheckMode { Off, Auto, On };

struct BiasCheckOptions {
    // Auto: on for the many-light integrators (bias_check_by_default), off for the others.
    BiasCheckMode mode = BiasCheckMode::Off;
    double share = 0.1;      // of the render's time the check may take, in (0, 0.5]
    int pixels = 256;        // pixels path traced (all of them on a smaller image)
    std::optional<int> spp;  // path samples per check pixel (a cap under a time limit)
};

// "auto", "on" or "off" (for the command line); throws UsageError otherwise.
BiasCheckMode parse_bias_check_mode(const std::string& s);
// Throws UsageError for options out of range (share, pixels, spp).
void validate(const BiasCheckOptions& options);
// The integrators whose defaults may keep a bias: the many-light ones.
bool bias_check_by_default(const std::string& integrator);
// Whether a render with `integrator` runs the check.
bool bias_check_enabled(const BiasCheckOptions& options, const std::string& integrator);

// The ratio of means of `image` to `reference` (per pixel, one channel) with the delta-method
// interval of step 3 at two-sided level `level` (0.95, 0.99). Undefined (nullopt) with fewer than
// two pixels or a reference sum that is not positive.
struct RatioInterval {
    double ratio = 0, lo = 0, hi = 0;
};
std::optional<RatioInterval> ratio_of_means(const std::vector<double>& image,
                                            const std::vector<double>& reference, double level);
// The two-sided Student-t quantile: t such that P(|T| <= t) = level with `df` degrees of freedom
// (Cornish-Fisher expansion; within 0.1% of the exact value for df >= 10).
double student_t_quantile(double level, double df);

struct BiasCheckResult {
    bool ran = false;
    int pixels = 0;
    int64_t path_samples = 0;  // in all
    int max_depth = 0;
    double seconds = 0;
    std::array<std::optional<RatioInterval>, 3> ci95, ci99;  // per channel
    // "ok", "off", or "none": no channel could be judged (no time left, a black image).
    std::string verdict = "none";
    double path_spp() const { return pixels > 0 ? double(path_samples) / pixels : 0.0; }
    nlohmann::json to_json() const;
    // One line for the command line's summary: the ratios, intervals and verdict.
    std::string summary() const;
    // The warning for the render's list when the verdict is "off", else empty.
    std::string warning() const;
};

// What the check needs from the render.
struct BiasCheckInput {
    const Scene& scene;
    const PerspectiveCamera& camera;
    const Filter& filter;
    const Image& image;                          // the render's image
    float max_component = 0, imaging_ratio = 1;  // the film's clamp and scale
    uint64_t seed = 0;                           // the render's seed
    int max_depth = 5;                           // the render's
    // Without a time limit (0): path samples per pixel (at least 1). Under one: the deadline,
    // in seconds from `start`, and spp (if given) caps the samples per pixel.
    int spp = 1;
    double time_limit = 0;
    std::chrono::steady_clock::time_point start;
    const std::atomic<bool>* cancel = nullptr;
};

// The path samples per check pixel without a time limit: the options' spp, else `share` of the
// render's samples (render_spp per pixel on width x height pixels) spread over the check pixels.
int bias_check_spp(const BiasCheckOptions& options, int render_spp, int width, int height);

BiasCheckResult run_bias_check(const BiasCheckInput& input, const BiasCheckOptions& options);

}  // namespace ml
