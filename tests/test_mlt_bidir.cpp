// Veach's partial bidirectional mutation for path-space MLT (bidir_mutation.h): its acceptance
// ratio against a brute-force evaluation of f and of the proposal densities T, MLT restricted to
// it against path tracing (area light; glass and mirrors) and BDPT (point-light caustics), the
// white furnace, and the settings that pick it.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bidir_test_helpers.h"
#include "integrators/mlt/bidir_mutation.h"
#include "lights/light_sampler.h"
#include "render/settings.h"
#include "sampling/sampler.h"

using namespace ml;

namespace {

// MLT with only the partial bidirectional mutation.
std::map<std::string, std::string> partial_only() {
    return {{"mlt.bootstrap", "20000"},       {"mlt.chains", "64"},
            {"mlt.bidirectional", "partial"}, {"mlt.whole_prob", "0"},
            {"mlt.bidirectional_prob", "1"},  {"mlt.lens_prob", "0"}};
}

// Brute force, for paths whose surfaces are all non-specular, from the vertices' positions
// alone: the measurement contribution f and the density with which the mutation regrows the
// vertices a + 1 .. b - 1 of a path (T(. -> path) for deletion (a, b)).
struct BruteForce {
    const BdptScene& ctx;

    static Vec3 dir(const PathVertex& from, const PathVertex& to) {
        return normalize(to.p() - from.p());
    }
    // Solid angle at `from` to area at `to`.
    static double to_area(const PathVertex& from, const PathVertex& to) {
        Vec3 d = to.p() - from.p();
        double d2 = length_squared(d);
        return std::abs(dot(to.ng(), d / float(std::sqrt(d2)))) / d2;
    }

    double f(const MltPath& x) const {
        const auto& v = x.v;
        const int n = int(v.size());
        Vec3 d01 = dir(v[0], v[1]);
        RGB c(float(ctx.camera.importance(Ray{v[0].p(), d01}) *
                    std::abs(dot(ctx.camera.forward(0.f), d01))));
        for (int k = 0; k + 1 < n; ++k) {
            Vec3 d = v[size_t(k + 1)].p() - v[size_t(k)].p();
            double d2 = length_squared(d);
            d = d / float(std::sqrt(d2));
            double g = std::abs(dot(v[size_t(k + 1)].ns(), d)) / d2;
            if (k > 0) g *= std::abs(dot(v[size_t(k)].ns(), d));
            c *= float(g);
        }
        for (int k = 1; k + 1 < n; ++k) {
            const PathVertex& p = v[size_t(k)];
            c *= p.bsdf.eval(dir(p, v[size_t(k - 1)]), dir(p, v[size_t(k + 1)]),
                             TransportMode::Radiance);
        }
        const PathVertex& l = v.back();
        c *= l.light->radiance(l.p(), l.ng(), l.si.uv, dir(l, v[size_t(n - 2)]));
        return c.luminance();
    }

    // Area density of vertex k made from the eye side (the lens: 1 for the pinhole's delta).
    double eye(const MltPath& x, int k) const {
        const auto& v = x.v;
        if (k == 0) return 1;
        if (k == 1) {
            float pos = 0, sa = 0;
            ctx.camera.pdf_we(Ray{v[0].p(), dir(v[0], v[1])}, &pos, &sa);
            return sa * to_area(v[0], v[1]);
        }
        const PathVertex& p = v[size_t(k - 1)];
        return p.bsdf.pdf_solid_angle(dir(p, v[size_t(k - 2)]), dir(p, v[size_t(k)]),
                                      TransportMode::Radiance) *
               to_area(p, v[size_t(k)]);
    }

    // Area density of vertex k made from the light side; the light itself by its area density
    // (sample_le's origin, for s = 1 as for s > 1).
    double light(const MltPath& x, int k) const {
        const auto& v = x.v;
        const int n = int(v.size());
        const PathVertex& l = v.back();
        float pos = 0, sa = 0;
        if (k == n - 1) {
            double pmf = ctx.light_sampler.pmf(l.light);
            l.light->pdf_le(Ray{l.p(), dir(l, v[size_t(n - 2)])}, l.ng(), &pos, &sa);
            return pmf * pos;
        }
        if (k == n - 2) {
            l.light->pdf_le(Ray{l.p(), dir(l, v[size_t(k)])}, l.ng(), &pos, &sa);
            return sa * to_area(l, v[size_t(k)]);
        }
        const PathVertex& p = v[size_t(k + 1)];
        return p.bsdf.pdf_solid_angle(dir(p, v[size_t(k + 2)]), dir(p, v[size_t(k)]),
                                      TransportMode::Importance) *
               to_area(p, v[size_t(k)]);
    }

    // The density of split l_E alone (l_E eye vertices, the rest from the light side).
    double split(const MltPath& x, int a, int b, int l_e) const {
        const int n = int(x.v.size()), t = a + 1 + l_e, s = n - t;
        if (s == 1 && t == 1) return 0;
        double p = 1;
        for (int k = a + 1; k < t; ++k) p *= eye(x, k);
        for (int k = t; k < b; ++k) p *= light(x, k);
        return p;
    }

    // T(. -> x) for deletion (a, b): p_d / positions times the mean over the splits; when
    // `drop` >= 0 that split's term is left out (a deliberately wrong T).
    double T(const MltPath& x, int a, int b, int drop = -1) const {
        const int n = int(x.v.size()), k_d = b - a, m = k_d - 1, e_min = a < 0 ? 1 : 0;
        double sum = 0;
        for (int l_e = e_min; l_e <= m; ++l_e)
            if (l_e != drop) sum += split(x, a, b, l_e);
        return deletion_probability(n, k_d) / (n + 2 - k_d) / (m + 1 - e_min) * sum;
    }
};

}  // namespace

TEST(MltBidir, DeletionProbabilitiesAreVeachsAndSumToOne) {
    for (int n : {2, 3, 5, 9}) {
        double sum = 0;
        for (int k = 0; k <= n + 3; ++k) sum += deletion_probability(n, k);
        EXPECT_NEAR(sum, 1.0, 1e-12) << n;
        EXPECT_EQ(deletion_probability(n, 1), 0.0);
        if (n >= 3) {
            EXPECT_NEAR(deletion_probability(n, 2) / deletion_probability(n, 3), 4, 1e-12);
        }
    }
}

TEST(MltBidir, AcceptanceRatioIsTheBruteForceProposalDensityRatio) {
    // Diffuse surfaces and an area light: every split counts, and f and T are plain products.
    // The mutation's ratio f(y) T(y -> x) / (f(x) T(x -> y)) comes from BDPT's strategy sums over
    // whole paths (the kept vertices cancelling); the brute force multiplies the regrown
    // vertices' densities. Leaving one split out of T must be seen.
    test::Bench bench(test::cornell_variant(), 32);
    BruteForce brute{*bench.ctx};
    auto sampler = create_sampler("independent", 1, 5);
    ScratchBuffer scratch_x, scratch_y;
    int pairs = 0, multi_split = 0, caught = 0;
    double worst = 0;
    for (int i = 0; pairs < 600 && i < 4000; ++i) {
        int depth = 1 + i % 4;
        scratch_x.reset();
        sampler->start_pixel_sample(Point2i{i, 1}, 0);
        auto x = sample_bdpt_path(*bench.ctx, *sampler, depth, scratch_x);
        if (!x || !(brute.f(*x) > 0)) continue;
        for (int j = 0; j < 8; ++j) {
            scratch_y.reset();
            sampler->start_pixel_sample(Point2i{i, 2}, j);
            BidirChoice c;
            auto p = mutate_bidirectional_partial(*bench.ctx, *x, *sampler, scratch_y, &c);
            if (!p) continue;
            const MltPath& y = p->y;
            ASSERT_EQ(y.v.size(), x->v.size());
            double expected =
                brute.f(y) * brute.T(*x, c.a, c.b) / (brute.f(*x) * brute.T(y, c.a, c.b));
            double err = std::abs(c.ratio / expected - 1);
            worst = std::max(worst, err);
            EXPECT_LT(err, 2e-3) << fmt::format("depth {} deletion ({}, {}) l_E {}: {} vs {}",
                                                depth, c.a, c.b, c.eye, c.ratio, expected);
            EXPECT_FLOAT_EQ(p->accept, float(std::min(1.0, c.ratio)));
            ++pairs;
            // The same with the last split left out of both densities.
            int m = c.b - c.a - 1, e_min = c.a < 0 ? 1 : 0;
            if (m - e_min < 1) continue;
            ++multi_split;
            double wrong =
                brute.f(y) * brute.T(*x, c.a, c.b, m) / (brute.f(*x) * brute.T(y, c.a, c.b, m));
            if (std::abs(c.ratio / wrong - 1) > 2e-3) ++caught;
        }
    }
    EXPECT_GE(pairs, 600);
    EXPECT_GT(caught, multi_split / 2) << "a T without one of its splits goes unnoticed";
    RecordProperty("worst_relative_error", fmt::format("{:.3g}", worst));
}

TEST(MltBidir, WhiteFurnaceHoldsAtDepthThree) { test::expect_mlt_furnace(partial_only()); }

TEST(MltBidir, AgreesWithPathOnTheCornellBox) {
    test::expect_mlt_agrees_with_path_on_cornell(partial_only(), "mlt (partial bidirectional)");
}

TEST(MltBidir, AgreesWithPathThroughGlassAndMirrors) {
    test::expect_mlt_agrees_with_path_through_glass(partial_only(), "mlt (partial bidirectional)");
}

TEST(MltBidir, AgreesWithBdptForPointLightCausticsThroughGlass) {
    test::expect_mlt_agrees_with_bdpt_on_caustics(partial_only(), "mlt (partial bidirectional)");
}

TEST(MltBidir, BadBidirectionalSettingsAreUsageErrors) {
    RenderOptions opt;
    opt.integrator = "mlt";
    opt.spp = 1;
    opt.width = opt.height = 8;
    opt.set = {{"mlt.bidirectional", "halfway"}};
    EXPECT_THROW(test::render_text(test::cornell_variant(), opt), UsageError);
    opt.set = {{"mlt.whole_prob", "1.5"}};
    EXPECT_THROW(test::render_text(test::cornell_variant(), opt), UsageError);
    opt.set = {{"mlt.bidirectional", "whole"}, {"mlt.bootstrap", "1000"}};
    EXPECT_NO_THROW(test::render_text(test::cornell_variant(), opt));
}
