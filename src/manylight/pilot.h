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

#include "core/color.h"
#include "core/math.h"
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

}  // namespace ml
