#include "integrators/pssmlt/bootstrap.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace ml {

MltSampler bootstrap_sampler(const MltParams& params, const PrimaryEstimator& estimator,
                             uint64_t index) {
    return MltSampler(params.seed, index, params.sigma, params.large_step_prob,
                      estimator.stream_count());
}

Bootstrap::Bootstrap(const PrimaryEstimator& estimator, const MltParams& params, int n,
                     const std::function<bool()>& stop) {
    const size_t depths = size_t(estimator.depth_count());
    // Grown chunk by chunk: a bootstrap that the time limit stops early never allocates (and
    // the kernel never zeroes) the whole n x depths array, hundreds of MB for 20M paths.
    std::vector<float> importance;
    ThreadLocal<ScratchBuffer> scratch;
    // Paths [p0, p1) of every stratum at a time: all of them at once without `stop`.
    const int chunk = stop ? 4096 : n;
    for (int p0 = 0; p0 < n; p0 += chunk) {
        const int p1 = std::min(n, p0 + chunk);
        importance.resize(size_t(p1) * depths);
        parallel_for_chunks(
            size_t(p0) * depths, size_t(p1) * depths, size_t(256), [&](size_t begin, size_t end) {
                ScratchBuffer& buf = scratch.local();
                for (size_t i = begin; i < end; ++i) {
                    MltSampler sampler = bootstrap_sampler(params, estimator, i);
                    int depth = int(i % depths);
                    importance[i] = mlt_importance(estimator.sample(sampler, depth, buf).L);
                    buf.reset();
                }
            });
        if (p1 < n && stop && stop()) {
            n = p1;
            importance.resize(size_t(n) * depths);
        }
    }
    const size_t count = size_t(n) * depths;
    // The running sums run stratum by stratum (position d * n + i holds path i of stratum d),
    // so chains started at evenly spread positions split over the strata in proportion to
    // their brightness. Summed in a fixed order: the same b whatever the schedule.
    m_n = size_t(n);
    m_depths = depths;
    m_cdf.resize(count);
    double sum = 0;
    for (size_t d = 0; d < depths; ++d)
        for (size_t i = 0; i < m_n; ++i) m_cdf[d * m_n + i] = sum += importance[i * depths + d];
    m_b = sum / double(n);
    double sum_sq = 0;
    for (size_t i = 0; i < m_n; ++i) {
        double x = 0;  // path i's importance over all strata
        for (size_t d = 0; d < depths; ++d) x += importance[i * depths + d];
        sum_sq += sqr(x - m_b);
    }
    if (n > 1) m_b_stderr = std::sqrt(sum_sq / double(n - 1) / double(n));
}

uint64_t Bootstrap::pick(double u) const {
    double target = u * m_cdf.back();
    // The first index whose running sum exceeds the target: zero-importance paths (equal
    // running sums) are never picked.
    auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), target);
    if (it == m_cdf.end()) --it;
    // Only when u * total rounds to the total: step back over trailing zero-importance paths.
    while (it != m_cdf.begin() && *it == *(it - 1)) --it;
    size_t k = size_t(it - m_cdf.begin());
    return uint64_t((k % m_n) * m_depths + k / m_n);
}

}  // namespace ml
