// The error floor of the cuts. Lightcuts stops refining a cut when every cluster's error bound is
// below a fraction (the `error` setting) of the estimate at that point: Weber's law, relative
// error. In a dark corner lit through a doorway, hundreds of clusters behind the walls keep
// bounds (visibility taken as 1) far above the tiny estimate, and the cut runs to max_cut for
// nothing: their values are zero. Perception has an absolute floor there too, so the tolerance
// is the error times the larger of the estimate and `floor` times the image's mean luminance.
//
// That mean is estimated before the render by a pilot: the integrator's own estimate (with a
// small cut) at a sparse grid of pixels, summed in a fixed order, so it is the same for a seed
// whatever the thread count.
#pragma once

#include <functional>
#include <vector>

#include "core/color.h"
#include "core/math.h"
#include "render/integrator.h"
#include "sampling/sampler.h"

namespace ml {

// Pixels the pilot visits: a regular grid of about this many.
constexpr int kPilotPixels = 1024;
// The pilot's cuts stop at this many clusters: unbiased and cheap, if noisy.
constexpr int kPilotMaxCut = 64;

// The mean over the pilot grid of estimate(pixel) (its luminance), >= 0; 0 for an empty film.
// `estimate` runs in parallel, one call per pixel, with the integrator's per-thread state: its
// randomness must come from the pixel's sampler sequence, so that the result is deterministic.
double pilot_mean_luminance(int width, int height,
                            const std::function<RGB(Point2i pixel)>& estimate);

// The tolerance of a cut: error times the larger of the estimate's luminance and the floor.
inline float cut_tolerance(float error, const RGB& estimate, float floor_luminance) {
    return error * std::max(estimate.luminance(), floor_luminance);
}

// Under a time limit: the cut cap that lets one pass over the film end in `seconds`. A cut's
// cost grows with its size; the full cuts of a pass over a large film (the kitchen at 320x180
// with mdlightcuts' defaults: about 35 CPU s) need not fit a short limit, and a pass cut short
// leaves pixels black. A cut stopped at a cap estimates the same sum, with more noise.
struct CutCapPlan {
    int cap = 0;                // the cap the pass should use, in [lowest, max_cut]
    double full_seconds = 0;    // one pass's predicted wall time at max_cut
    double capped_seconds = 0;  // ... at `cap`
    double mean_full_size = 0;  // the probe's mean cut size at max_cut
    // Where even `lowest` does not fit, the share of the pass's samples that does (< 1; else
    // 1): a pixel's time at `lowest` taken as linear in its samples, through the probe's visits
    // with all and with half of them; without the half visit, the time's ratio times 0.8 (the
    // cut's cost does not shrink with the samples).
    double samples_scale = 1;
    // The share of a pass's time at `cap` that does not shrink with its samples (the cuts'
    // refinement, against the samples' rays and gather points), through the probe's visits with
    // all and half of the samples; 1 where they do not tell.
    double fixed_share = 1;
};

// The samples a pass takes under `plan`: `samples` times plan.samples_scale, at least 1.
int pass_samples(int samples, const CutCapPlan& plan);

// Under a time limit, the passes one VPL set (and its light tree) serves where a new set every
// pass (vpl.sets=pass) would take more than `share` of the passes' time: the least whole number
// of passes that keeps set_seconds within share of them, pass_seconds being a pass's predicted
// time without its set (CutCapPlan::capped_seconds). Only where the pass's cuts are small
// (mean_cut, CutCapPlan::mean_full_size, at most kSetReuseMaxCut pairs): a cut stops once its
// pairs' bounds are within its tolerance of the eye paths' part, so a cut of a few pairs means
// the VPLs carry little of the image, and their sets' spread little of its error. Where the cuts
// are large, the sets' spread is much of the error and a new set every pass pays (veach-ajar at
// 128x128: four passes a set kept the relMSE and doubled the means' error). 1 also where the set
// is cheap or nothing is measured (pass_seconds or share 0). The sets stay independent draws, so
// the image still converges; only fewer of them are drawn.
constexpr double kSetReuseMaxCut = 8;
int passes_per_set(double set_seconds, double pass_seconds, double share, double mean_cut);

// Under a time limit, once the whole passes that fit are done: the samples of one last pass
// predicted to end within kRoundTimeShare of `seconds` left, a pass of k of `pass_samples`
// samples taken to cost pass_seconds * (fixed_share + (1 - fixed_share) k / pass_samples).
// In [0, pass_samples - 1]; 0 when none fits.
int remainder_samples(int pass_samples, double pass_seconds, double fixed_share, double seconds);

// The last pass under a time limit: its samples (0: none) and the share of the whole passes'
// mean cut size its cuts may take (1: the passes' own cap).
struct LastPass {
    int samples = 0;
    double cut_share = 1;
};
// The smallest share of a whole pass's time that a last pass scaled down as a whole may take:
// below it, its cuts would be a handful of pairs.
constexpr double kMinLastPassShare = 0.1;
// remainder_samples's pass where one fits. Where even its fixed part (the cuts) overruns the time
// left, a pass scaled down as a whole to the share phi of a pass that fills kRoundTimeShare of
// `seconds`: phi of the samples (at least 1) and cuts of phi of the mean size (a cut's time
// taken as proportional to its pairs), if phi is at least kMinLastPassShare. A fixed share of 1
// (nothing measured) scales nothing.
LastPass last_pass(int pass_samples, double pass_seconds, double fixed_share, double seconds);

// The cap of a last pass's cuts: plan.cut_share of the whole passes' mean cut size, at least
// kMinLastPassCut and at most `cap` (the whole passes'); `cap` where the share is 1.
constexpr int kMinLastPassCut = 16;
int last_pass_cap(const LastPass& plan, double mean_size, int cap);

// The passes of an integrator whose passes shade the whole film (mdlightcuts, bdlightcuts):
// fn(pixel, first, samples) shades the pixel's samples [first, first + samples) as one pass.
// Passes of `pass_samples` samples run through render_pixels up to ctx.spp; under a time limit,
// where the time left after the last whole pass has no room for another, one last pass of
// remainder_samples fills it (each pixel's passes add to the film by their samples' weights, so
// a pass of fewer samples keeps its mean right). Across ranks, every rank takes the least
// remainder. Returns what was done (a pass cut short by the limit does not count).
struct SamplePasses {
    int64_t samples = 0;        // per pixel, in the passes that counted
    int64_t whole = 0;          // whole passes among them
    int last_samples = 0;       // the last pass's samples (0: none ran or it was cut short)
    double last_cut_share = 1;  // the last pass's LastPass::cut_share
    double pass_seconds = 0;    // the whole passes' mean wall time
};
// Before the last pass, last(plan) tells the integrator its shape (its cuts' share of the mean
// size: the integrator sets the cap its fn uses from its own figures of the whole passes). With
// `after_first`, the first pass runs over the whole film (on every rank) before any other
// starts, and after_first() runs between them (adaptive sampling from the first pass). With
// `begin_pass`, every pass (the last one too) is begun by begin_pass(p), p = 0, 1, ..., once the
// pass before has ended on every pixel (render_pixel_blocks): the integrator's new VPL set.
// With ctx.checkpoint the passes are its units (the last pass one more): a resumed render
// begins at the pass the checkpoint stopped in (pixels a stop left ahead skip it), with
// begin_pass(p) for it and after_first() first where it is past the first pass (the integrator
// restores what after_first needs); the end, or a stop, is saved. The integrator saves what its
// passes need in the checkpoint's state (Checkpoint::set_state).
SamplePasses render_sample_passes(
    const RenderContext& ctx, int pass_samples, double fixed_share,
    const std::function<void(Point2i pixel, int first, int samples)>& fn,
    const std::function<void(const LastPass& plan)>& last = {},
    const std::function<void()>& after_first = {},
    const std::function<void(int64_t pass)>& begin_pass = {});

// The share of the time left that a time-limited render plans its first pass to take.
constexpr double kFirstPassTimeShare = 0.75;

// Pixels the timing probe visits: about this many, in square blocks of kCutProbeBlock on a
// side centred on a regular grid.
constexpr int kCutProbePixels = 256;
constexpr int kCutProbeBlock = 4;
// Each of the probe's two visits of the grid stops starting pixels past this share of `seconds`.
constexpr double kCutProbeShare = 0.05;

// What the timing probe measured: wall seconds per probed pixel (all threads working) at cap
// `lowest` and at max_cut (< 0: the probe's time ran out before any pixel), the mean cut size
// at `lowest`, and the cut sizes at max_cut.
struct CutProbe {
    double low_seconds = -1, full_seconds = -1;
    // At `lowest` with half the pass's samples (< 0: not measured, a pass of one sample).
    double half_seconds = -1;
    double low_mean_size = 0;
    std::vector<int> full_sizes;
};

// The largest cap in [lowest, max_cut] that a pass over `film_pixels` pixels is predicted to
// finish in `seconds`: a pixel's time is taken as a + b * (its cut size), fitted to the probe's
// two visits, and a cap c as making each probed cut min(size at max_cut, r c), r the ratio of
// the mean cut at `lowest` to `lowest` (a cut may end a little past its cap). max_cut
// when the full cuts fit; `lowest` when nothing does or the probe has no figure.
CutCapPlan choose_cut_cap(const CutProbe& probe, double film_pixels, int lowest, int max_cut,
                          double seconds);

// Probes blocks on a sparse grid of the film (about kCutProbePixels pixels, in parallel) twice:
// with cap `lowest` and with `max_cut`, each visit timed and stopped past kCutProbeShare of
// `seconds`, and a third time at `lowest` with half the pass's `samples` (when it has 2 or more);
// shade(pixel, cap, samples) shades one pixel's pass of `samples` samples with cuts stopped at
// `cap` and returns the
// cut's size.
CutProbe probe_cuts(int width, int height, int lowest, int max_cut, int samples, double seconds,
                    const std::function<int(Point2i pixel, int cap, int samples)>& shade);

// What a many-light integrator with whole-film passes (mdlightcuts, bdlightcuts) runs before its
// first: under ctx's time limit, probe_cuts, then choose_cut_cap for kFirstPassTimeShare of
// the time left after the probe (across ranks, each renders its share of the film and all take
// the least cap); without one, max_cut.
CutCapPlan plan_pass_cut_cap(const RenderContext& ctx, int max_cut, int samples,
                             const std::function<int(Point2i pixel, int cap, int samples)>& shade);

}  // namespace ml
