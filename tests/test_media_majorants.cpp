// The majorant grids of the grid media (Medium::majorants): finer bounds of the extinction, cell
// by cell, that delta and ratio tracking step through. The bound must hold at every point (a
// wrong cell is a biased image), and the transport through them must not change.

#include <gtest/gtest.h>

#include <string>

#include "chi2.h"
#include "majorant_check.h"
#include "media/medium.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"
#include "sampling/sampler.h"
#include "scene/scene_desc.h"
#include "transport/volume_path.h"

using namespace ml;
using namespace ml::test;

namespace {

// nx x ny x nz values, most zero, a few dense (up to 5), from `seed`.
std::string sparse_values(int n, uint64_t seed, bool rgb) {
    Rng rng(seed);
    std::string s;
    for (int i = 0; i < n; ++i) {
        const float u = rng.next_float();
        const float v = u < 0.85f ? 0.f : 5 * rng.next_float();
        for (int c = 0; c < (rgb ? 3 : 1); ++c)
            s += std::to_string(rgb ? v * (0.5f + 0.25f * float(c)) : v) + " ";
    }
    return s;
}

}  // namespace

TEST(MediumMajorants, GridCellsBoundTheExtinctionAlongEveryRay) {
    // Sparse grids (85% empty) of odd sizes, under a rotation and a stretch, so that cells of the
    // 16^3 majorant grid straddle the density's cells: along random rays the segments adjoin and
    // bound sigma_a + sigma_s at every point tried.
    const std::string transform = "Rotate 30 1 2 3\nScale 2 0.5 1\n";
    const std::string box = "\"point3 p0\" [ -1 -2 0 ] \"point3 p1\" [ 3 1 2 ]";
    const std::string uniform = transform +
                                "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" " + box +
                                " \"integer nx\" [ 7 ] \"integer ny\" [ 5 ] \"integer nz\" [ 19 ]"
                                " \"float density\" [ " +
                                sparse_values(7 * 5 * 19, 3, false) +
                                "] \"rgb sigma_a\" [ 0.5 1 1.5 ] \"rgb sigma_s\" [ 2 1 0.5 ]\n"
                                "WorldBegin\n";
    const std::string rgb = transform + "MakeNamedMedium \"g\" \"string type\" \"rgbgrid\" " + box +
                            " \"integer nx\" [ 23 ] \"integer ny\" [ 3 ] \"integer nz\" [ 6 ]"
                            " \"rgb sigma_a\" [ " +
                            sparse_values(23 * 3 * 6, 4, true) + "] \"rgb sigma_s\" [ " +
                            sparse_values(23 * 3 * 6, 5, true) + "] \"float scale\" [ 2 ]\n" +
                            "WorldBegin\n";
    for (const std::string& text : {uniform, rgb}) {
        const SceneDesc desc = parse_scene_string(text, ".", "test.pbrt");
        const Medium& m = *desc.media[0];
        SCOPED_TRACE(m.type());
        // The box in world space, roughly: the checker widens it and shoots rays through it.
        const double saved = expect_majorants_bound(m, Vec3(-4, -4, -4), Vec3(6, 4, 4), 3000, 11);
        EXPECT_GT(saved, 0.2) << "the finer bounds should be below the one bound somewhere";
    }
}

TEST(MediumMajorants, AHomogeneousMediumAndACloudKeepOneSegment) {
    const SceneDesc desc = parse_scene_string(
        "MakeNamedMedium \"h\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ 1 2 3 ]\n"
        "MakeNamedMedium \"c\" \"string type\" \"cloud\" \"point3 p0\" [ 0 0 0 ] "
        "\"point3 p1\" [ 1 1 1 ]\nWorldBegin\n",
        ".", "test.pbrt");
    for (const auto& m : desc.media) {
        SCOPED_TRACE(m->type());
        EXPECT_EQ(expect_majorants_bound(*m, Vec3(0, 0, 0), Vec3(1, 1, 1), 300, 12), 0.0);
    }
}

TEST(MediumMajorants, TrackingThroughTheCellsTransmitsAsTheDensityIntegrates) {
    // A camera inside a sparse absorbing grid (coloured: spectral tracking) looks orthographically
    // through it at an emitter of radiance 1: each pixel is the transmittance exp(-int sigma_a)
    // along its rays. The image's mean against the same integral by quadrature over the film.
    const std::string values = sparse_values(9 * 9 * 9, 7, false);
    const std::string scene =
        "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"point3 p0\" [ -1 -1 -1 ] "
        "\"point3 p1\" [ 1 1 1 ] \"integer nx\" [ 9 ] \"integer ny\" [ 9 ] \"integer nz\" [ 9 ] "
        "\"float density\" [ " +
        values +
        "] \"rgb sigma_a\" [ 0.2 0.4 0.8 ] \"rgb sigma_s\" [ 0 0 0 ]\n"
        "MediumInterface \"\" \"g\"\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"orthographic\"\n"
        "Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n"
        "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\n"
        "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -3 -3 2  -3 3 2  3 3 2  3 -3 2 ]\n";
    RenderOptions opt;
    opt.spp = 64;
    opt.seed = 5;
    const Image img = render_text(scene, opt).image;
    const SceneDesc desc = parse_scene_string(scene, ".", "test.pbrt");
    const Medium& m = *desc.media[0];
    // Quadrature: 96 x 96 rays over the film's square [-1, 1]^2, 400 steps through the box.
    double expected[3] = {0, 0, 0};
    const int n = 96, steps = 400;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float x = -1 + 2 * (float(i) + 0.5f) / float(n),
                        y = -1 + 2 * (float(j) + 0.5f) / float(n);
            RGB tau;
            for (int k = 0; k < steps; ++k)
                tau += m.at(Vec3(x, y, -1 + 2 * (float(k) + 0.5f) / float(steps))).sigma_a *
                       (2.f / float(steps));
            expected[0] += std::exp(-double(tau.r)) / (n * n);
            expected[1] += std::exp(-double(tau.g)) / (n * n);
            expected[2] += std::exp(-double(tau.b)) / (n * n);
        }
    for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (const RGB& p : img.pixels) mean += p[c];
        mean /= double(img.pixels.size());
        EXPECT_NEAR(mean, expected[c], 0.01) << "channel " << c;
        EXPECT_LT(expected[c], 0.95) << "the medium should absorb";
    }
}

TEST(MediumMajorants, TheMajorantsCollisionProcessHasTheDensityItsTransmittanceGives) {
    // Metropolis light transport places medium vertices at the first collision of the majorant's
    // process and weighs them by its density in closed form: P(t < s) = 1 - Tmaj(s), and the
    // density sigma_maj(t) Tmaj(t). Along rays through a sparse grid's cells: a chi-square of the
    // drawn distances (16 bins and "none") against Tmaj's differences, and sigma_maj Tmaj against
    // Tmaj's derivative.
    const SceneDesc desc = parse_scene_string(
        "Rotate 30 1 2 3\nMakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "
        "\"point3 p0\" [ -1 -1 -1 ] \"point3 p1\" [ 1 1 1 ] \"integer nx\" [ 9 ] "
        "\"integer ny\" [ 9 ] \"integer nz\" [ 9 ] \"float density\" [ " +
            sparse_values(9 * 9 * 9, 9, false) +
            "] \"rgb sigma_a\" [ 0.2 0.4 0.8 ] \"rgb sigma_s\" [ 0.5 0.5 0.5 ]\nWorldBegin\n",
        ".", "test.pbrt");
    const Medium& m = *desc.media[0];
    auto sampler = create_sampler("independent", 1, 17);
    Rng rng(23);
    const int rays = 12, bins = 16, draws = 20000;
    for (int r = 0; r < rays; ++r) {
        const Vec3 o(0.8f * rng.next_float() - 0.4f, 0.8f * rng.next_float() - 0.4f, -2.5f);
        const Vec3 d =
            normalize(Vec3(0.3f * rng.next_float() - 0.15f, 0.3f * rng.next_float() - 0.15f, 1));
        const Ray ray{o, d};
        const float tmax = 4;
        std::vector<double> count(bins + 1, 0.0), p(bins + 1, 0.0);
        sampler->start_pixel_sample(Point2i{r, 0}, 0);
        for (int i = 0; i < draws; ++i) {
            const std::optional<float> t = first_majorant_collision(m, ray, tmax, *sampler);
            count[t ? std::min(bins - 1, int(*t / tmax * bins)) : bins] += 1;
        }
        for (int b = 0; b < bins; ++b)
            p[b] = majorant_transmittance(m, ray, tmax * float(b) / bins) -
                   majorant_transmittance(m, ray, tmax * float(b + 1) / bins);
        p[bins] = majorant_transmittance(m, ray, tmax);
        double stat = 0;
        int dof = -1;
        for (int b = 0; b <= bins; ++b) {
            if (p[b] * draws < 5) continue;
            stat += (count[b] - p[b] * draws) * (count[b] - p[b] * draws) / (p[b] * draws);
            ++dof;
        }
        EXPECT_GT(chi2::chi2_survival(stat, dof), chi2::sidak_alpha(0.01, rays))
            << "ray " << r << ": chi-square " << stat << " over " << dof << " dof";
        EXPECT_LT(p[bins], 0.9) << "the ray should cross the medium";
        // The density: sigma_maj(t) Tmaj(t) = -dTmaj/dt inside a cell.
        for (float t = 0.05f; t < tmax; t += 0.1f) {
            const float h = 1e-3f;
            if (majorant_at(m, ray, t - h, tmax) != majorant_at(m, ray, t + h, tmax)) continue;
            const double derivative = (double(majorant_transmittance(m, ray, t - h)) -
                                       majorant_transmittance(m, ray, t + h)) /
                                      (2 * h);
            EXPECT_NEAR(majorant_at(m, ray, t, tmax) * majorant_transmittance(m, ray, t),
                        derivative, 2e-3 + 1e-2 * derivative)
                << "ray " << r << " at t " << t;
        }
    }
}
