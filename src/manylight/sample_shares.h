// Adaptive sampling for the integrators whose passes shade the whole film (bdlightcuts): after
// a first pass of the same samples everywhere, each pixel takes a share of the later passes'
// samples in proportion to the noise around it. The best split of a budget of samples between
// pixels whose samples cost alike puts n_i in proportion to sigma_i, the standard deviation of
// one sample relative to the pixel (relMSE's: over value^2 + 0.01).
//
// A pixel's share comes from its neighbours' noise alone, never its own: a pixel whose first
// pass drew a spike would otherwise take more samples just then, which dilutes the spike and
// darkens the pixel on average (and the reverse where the first pass drew low). Its neighbours'
// samples are independent of its own, so its share is too, and every pass's estimate keeps its
// mean. The neighbourhood (kShareRadius around the pixel) is where glossy highlights' rare
// samples and a shadow's edges repeat: the noise of a region, not of a sample.
#pragma once

#include <functional>
#include <vector>

#include "manylight/pilot.h"

namespace ml {

constexpr int kShareRadius = 3;           // a 7x7 neighbourhood, the pixel itself left out
constexpr float kMinSampleShare = 0.25f;  // of the mean: no pixel starves
constexpr float kMaxSampleShare = 4.f;    // ... nor takes a whole pass's worth of others'

// Each pixel's share of the samples, from `relative_variance` (one per pixel, row by row, >= 0;
// non-finite values count as 0): the square root of its neighbours' mean, over the film's mean
// of those, clamped to [kMinSampleShare, kMaxSampleShare] and scaled so that the shares average
// 1. All 1 where no pixel has any variance, or the input is not one value per pixel.
std::vector<float> neighbour_sample_shares(int width, int height,
                                           const std::vector<float>& relative_variance);

// A pixel's relative variance for neighbour_sample_shares: the variance of its estimate over
// value^2 + 0.01, value being the estimate's luminance.
inline float relative_variance(float variance, float value) {
    return variance / (value * value + 0.01f);
}

// render_sample_passes with adaptive sampling. fn(pixel, first, samples) shades one pixel pass
// (samples first ... first + samples - 1 of the pixel) and returns its relative_variance (only
// the first pass's is used). The first pass takes `pass_samples` everywhere. Then each pass
// gives a pixel its share s of the pass's samples, as round(s) passes (at least 1) of equal
// samples (at least 1 each), its samples numbered on from its last: an integrator whose pass
// has a noise of its own (bdlightcuts' cut, one per pass) averages more of it where the pixel
// is noisy. Across ranks, the first pass's variances are summed and broadcast, so that every
// rank plans the same shares. `max_share`, if given, receives the largest share. `begin_pass` as
// render_sample_passes takes it. With ctx.checkpoint, the first pass's variances and the pixels'
// sample counts are saved with the integrator's state (its key "adaptive"), and a resumed render
// plans the same shares from them.
SamplePasses render_adaptive_passes(
    const RenderContext& ctx, int pass_samples, double fixed_share,
    const std::function<float(Point2i pixel, int first, int samples)>& fn,
    const std::function<void(const LastPass& plan)>& last = {}, float* max_share = nullptr,
    const std::function<void(int64_t pass)>& begin_pass = {});

}  // namespace ml
