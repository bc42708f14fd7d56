// The primary-sample-space sampler: exact restore on reject, uniform large steps, normal small
// steps (also when applied lazily), streams, determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "chi2.h"
#include "core/error.h"
#include "sampling/mlt_sampler.h"

using namespace ml;

namespace {

// Chi-square p-value of `values` in [0,1) against the distribution with CDF `cdf` on `bins`
// equal bins of [0,1).
template <typename Cdf>
double binned_p_value(const std::vector<double>& values, int bins, Cdf cdf) {
    std::vector<double> count(bins, 0.0);
    for (double v : values) count[std::min(bins - 1, int(v * bins))] += 1;
    double stat = 0;
    for (int i = 0; i < bins; ++i) {
        double expected = values.size() * (cdf(double(i + 1) / bins) - cdf(double(i) / bins));
        stat += (count[i] - expected) * (count[i] - expected) / expected;
    }
    return chi2::gamma_q(0.5 * (bins - 1), 0.5 * stat);
}

double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// The wrapped difference of two values of one coordinate, in [-0.5, 0.5).
double wrapped_difference(double a, double b) {
    double d = b - a;
    return d - std::floor(d + 0.5);
}

}  // namespace

TEST(MltSampler, NormalQuantileInvertsTheCdf) {
    for (double u : {1e-12, 1e-6, 0.001, 0.02, 0.0243, 0.1, 0.5, 0.7, 0.975, 0.99, 1 - 1e-9})
        EXPECT_NEAR(phi(standard_normal_quantile(u)), u, 1e-12 + 1e-9 * u) << u;
    EXPECT_DOUBLE_EQ(standard_normal_quantile(0.5), 0.0);
    EXPECT_NEAR(standard_normal_quantile(0.975), 1.959963984540054, 1e-12);
}

TEST(MltSampler, SameSeedAndIndexGiveTheSameSamples) {
    MltSampler a(5, 17, 0.01f, 0.3f, 2), b(5, 17, 0.01f, 0.3f, 2), c(5, 18, 0.01f, 0.3f, 2);
    for (int i = 0; i < 8; ++i) {
        float va = a.get_1d(), vb = b.get_1d(), vc = c.get_1d();
        EXPECT_EQ(va, vb);
        EXPECT_NE(va, vc);
    }
}

TEST(MltSampler, StreamsInterleaveDimensions) {
    MltSampler s(1, 2, 0.01f, 0.3f, 3);
    s.start_stream(2);
    float l0 = s.get_1d(), l1 = s.get_1d();
    s.start_stream(0);
    float c0 = s.get_1d();
    ASSERT_EQ(s.dimension_count(), 6u);  // stream 2's second sample is dimension 2 + 3
    EXPECT_EQ(s.value(2), l0);
    EXPECT_EQ(s.value(5), l1);
    EXPECT_EQ(s.value(0), c0);
    // Reading a stream again in the same iteration gives the same values.
    s.start_stream(2);
    EXPECT_EQ(s.get_1d(), l0);
    EXPECT_THROW(s.start_stream(3), InternalError);
    EXPECT_THROW(MltSampler(1, 2, 0.f, 0.3f, 3), UsageError);
    EXPECT_THROW(MltSampler(1, 2, 0.01f, 1.5f, 3), UsageError);
}

TEST(MltSampler, RejectRestoresExactly) {
    // A chain of mixed steps; the proposal sometimes reads more coordinates than the state has
    // (the path grew). After every reject the state must be bit-identical to before, and the
    // iteration count back where it was.
    // Both streams are read equally, so every coordinate that exists has been read (a never-read
    // coordinate has no value yet: it is drawn when first read).
    MltSampler s(3, 9, 0.05f, 0.3f, 2);
    for (int stream = 0; stream < 2; ++stream) {
        s.start_stream(stream);
        for (int i = 0; i < 3; ++i) s.get_1d();
    }
    Rng pick(12345);
    int rejects = 0;
    for (int it = 0; it < 2000; ++it) {
        std::vector<float> before;
        for (size_t d = 0; d < s.dimension_count(); ++d) before.push_back(s.value(d));
        int64_t iteration = s.iteration();
        s.start_iteration();
        // Every existing coordinate is read (so none holds a stale value that an accepted large
        // step has lazily invalidated), sometimes a few more.
        int per_stream = int(s.dimension_count() / 2);
        if (per_stream < 20) per_stream += int(pick.next_u32() % 3);
        for (int stream = 0; stream < 2; ++stream) {
            s.start_stream(stream);
            for (int k = 0; k < per_stream; ++k) s.get_1d();
        }
        if (pick.next_float() < 0.5f) {
            s.reject();
            ++rejects;
            EXPECT_EQ(s.iteration(), iteration);
            for (size_t d = 0; d < before.size(); ++d)
                ASSERT_EQ(s.value(d), before[d]) << "iteration " << it << " dimension " << d;
        } else {
            s.accept();
        }
    }
    EXPECT_GT(rejects, 800);
}

TEST(MltSampler, RejectedProposalIsReplayedFromTheOldState) {
    // Two samplers with the same sequence: one rejects a proposal, the other never makes it;
    // the next small step of the first must start from the state they share, i.e. the lazy
    // step counts only accepted iterations.
    MltSampler s(8, 1, 0.02f, 0.0f, 1);
    for (int i = 0; i < 3; ++i) s.get_1d();
    std::vector<float> state = {s.value(0), s.value(1), s.value(2)};
    for (int trial = 0; trial < 50; ++trial) {
        s.start_iteration();
        for (int i = 0; i < 3; ++i) s.get_1d();
        s.reject();
    }
    for (int i = 0; i < 3; ++i) EXPECT_EQ(s.value(i), state[i]);
    s.start_iteration();
    s.get_1d();
    // One small step from the old value, not 51 accumulated ones.
    EXPECT_LT(std::abs(wrapped_difference(state[0], s.value(0))), 6 * 0.02);
}

TEST(MltSampler, LargeStepsAreUniform) {
    MltSampler s(2, 4, 0.01f, 1.0f, 1);
    std::vector<double> values, pairs_product;
    for (int it = 0; it < 20000; ++it) {
        s.start_iteration();
        ASSERT_TRUE(s.is_large_step());
        float a = s.get_1d(), b = s.get_1d();
        values.push_back(a);
        values.push_back(b);
        pairs_product.push_back((a - 0.5) * (b - 0.5));
        s.accept();
    }
    EXPECT_GT(binned_p_value(values, 40, [](double x) { return x; }), 1e-3);
    // Coordinates of one proposal are uncorrelated: E[(a-1/2)(b-1/2)] = 0, sd 1/12/sqrt(n).
    double m = 0;
    for (double p : pairs_product) m += p;
    m /= pairs_product.size();
    EXPECT_LT(std::abs(m), 5 * (1.0 / 12) / std::sqrt(double(pairs_product.size())));
}

TEST(MltSampler, LargeStepProbabilityIsHonoured) {
    MltSampler s(2, 5, 0.01f, 0.3f, 1);
    int large = 0, n = 20000;
    for (int it = 0; it < n; ++it) {
        s.start_iteration();
        large += s.is_large_step();
        s.get_1d();
        s.accept();
    }
    double sd = std::sqrt(n * 0.3 * 0.7);
    EXPECT_NEAR(large, 0.3 * n, 5 * sd);
}

namespace {

// The wrapped differences of one coordinate over `gap` accepted small steps in which it was not
// read: lazily applied, they must be N(0, sigma^2 gap) (wrapped; sigma is small enough that
// wrapping the difference loses nothing).
std::vector<double> small_step_differences(float sigma, int gap, int n) {
    MltSampler s(11, uint64_t(gap), sigma, 0.0f, 1);
    s.get_1d();
    std::vector<double> diffs;
    for (int i = 0; i < n; ++i) {
        float before = s.value(0);
        for (int k = 0; k < gap - 1; ++k) {
            s.start_iteration();
            s.accept();  // coordinate 0 untouched
        }
        s.start_iteration();
        s.start_stream(0);
        s.get_1d();
        s.accept();
        diffs.push_back(wrapped_difference(before, s.value(0)));
    }
    return diffs;
}

}  // namespace

TEST(MltSampler, SmallStepsAreNormalWithSigma) {
    for (int gap : {1, 9}) {
        float sigma = 0.02f;
        double sd = sigma * std::sqrt(double(gap));
        std::vector<double> d = small_step_differences(sigma, gap, 20000);
        // Binned against the normal CDF over +-4 sd, mapped onto [0,1).
        std::vector<double> mapped;
        for (double x : d) mapped.push_back(std::clamp((x / sd + 4) / 8, 0.0, 0.999999));
        double p = binned_p_value(mapped, 32, [](double t) {
            if (t <= 0) return 0.0;
            if (t >= 1) return 1.0;
            double lo = phi(-4), hi = phi(4);
            // Mass outside +-4 sd (6e-5) is folded into the end bins.
            double v = phi(8 * t - 4);
            return t < 1.0 / 32 ? v - lo : (t > 31.0 / 32 ? v + (1 - hi) : v);
        });
        EXPECT_GT(p, 1e-3) << "gap " << gap;
        double mean = 0, var = 0;
        for (double x : d) mean += x;
        mean /= d.size();
        for (double x : d) var += (x - mean) * (x - mean);
        var /= d.size() - 1;
        EXPECT_LT(std::abs(mean), 5 * sd / std::sqrt(double(d.size()))) << "gap " << gap;
        // The sample variance's relative sd is sqrt(2/n) = 1% here.
        EXPECT_NEAR(var / (sd * sd), 1.0, 0.05) << "gap " << gap;
    }
}

TEST(MltSampler, ValuesStayInTheUnitInterval) {
    MltSampler s(4, 4, 0.3f, 0.1f, 2);
    for (int it = 0; it < 5000; ++it) {
        s.start_iteration();
        for (int k = 0; k < 6; ++k) {
            float v = s.get_1d();
            ASSERT_GE(v, 0.f);
            ASSERT_LT(v, 1.f);
        }
        if (it % 3)
            s.accept();
        else
            s.reject();
    }
}
