// The bootstrap of primary-sample-space MLT: independent paths (fresh MltSamplers, every number
// uniform) in every depth stratum estimate the image's total brightness b, which scales the
// chains' splats, and the chains start from bootstrap paths picked in proportion to their
// brightness, so they start in their stationary distribution (no burn-in).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "integrators/pssmlt/estimator.h"

namespace ml {

struct MltParams {
    uint64_t seed = 0;
    float sigma = 0.01f;
    float large_step_prob = 0.3f;
};

// The scalar a chain's acceptance follows: the contribution's luminance (0 for what is not a
// finite, positive number).
inline float mlt_importance(const RGB& L) {
    float y = L.luminance();
    return std::isfinite(y) && y > 0 ? y : 0.f;
}

// The sampler of bootstrap path `index` (path i of stratum d has index i * depth_count + d): a
// chain restarting it with the same index sees the same numbers, so the same path.
MltSampler bootstrap_sampler(const MltParams& params, const PrimaryEstimator& estimator,
                             uint64_t index);

class Bootstrap {
public:
    // `n` paths per stratum, evaluated in parallel (deterministically). With `stop`, they are
    // evaluated in chunks and the bootstrap keeps the paths done when stop() first says true
    // (a time limit): any prefix of the paths is as valid a bootstrap, only smaller.
    Bootstrap(const PrimaryEstimator& estimator, const MltParams& params, int n,
              const std::function<bool()>& stop = {});
    int paths_per_stratum() const { return int(m_n); }
    // The mean importance per pixel sample, summed over strata: the image's mean luminance.
    double b() const { return m_b; }
    // The standard error of b (paths i of all strata summed are independent samples of b).
    double b_stderr() const { return m_b_stderr; }
    // A bootstrap index (path i of stratum d is i * depth_count + d) with probability
    // proportional to its importance, for u uniform in [0, 1). Strata are contiguous in u, in
    // order, so evenly spread u values divide chains among strata by their brightness.
    uint64_t pick(double u) const;
    size_t size() const { return m_cdf.size(); }

private:
    std::vector<double> m_cdf;  // running sums of the importances, stratum by stratum
    size_t m_n = 0, m_depths = 0;
    double m_b = 0, m_b_stderr = 0;
};

}  // namespace ml
