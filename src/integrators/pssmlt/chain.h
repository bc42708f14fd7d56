// One Markov chain of primary-sample-space MLT (Kelemen et al. 2002): it starts at a bootstrap
// path, proposes small or large steps of its MltSampler, accepts with probability
// min(1, I(proposed) / I(current)) and splats both states weighted by their expected share
// (the "expected value" estimator), so rejected proposals still contribute.
#pragma once

#include <cstdint>
#include <vector>

#include "integrators/pssmlt/bootstrap.h"
#include "render/splats.h"

namespace ml {

class MarkovChain {
public:
    // Chain `index` of `count` in the render with `params`: its starting path and its random
    // numbers depend on (params.seed, index, count) only.
    MarkovChain(const PrimaryEstimator& estimator, const Bootstrap& bootstrap,
                const MltParams& params, uint64_t index, uint64_t count);
    // Runs `n` mutations, adding their splats (before the image's scale b / (mutations per
    // pixel)) to `out`.
    void run(int64_t n, SplatList& out, ScratchBuffer& scratch);

    int64_t proposed() const { return m_proposed; }
    int64_t accepted() const { return m_accepted; }
    int depth() const { return m_depth; }
    // The chain's whole state, to continue exactly (checkpoints); restore() takes what state()
    // gave the same chain (same index, count and parameters).
    nlohmann::json state() const;
    void restore(const nlohmann::json& state);

private:
    void splat(const PrimaryPathSample& s, float weight, SplatList& out) const;

    const PrimaryEstimator& m_estimator;
    Rng m_rng;         // the chain's own choices: the starting path and acceptance
    uint64_t m_start;  // the bootstrap path it starts from
    MltSampler m_sampler;
    int m_depth;
    bool m_started = false;
    PrimaryPathSample m_current;
    float m_current_importance = 0;
    int64_t m_proposed = 0, m_accepted = 0;
};

}  // namespace ml
