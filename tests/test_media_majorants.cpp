// The majorant grids of the grid media (Medium::majorants): finer bounds of the extinction, cell
// by cell, that delta and ratio tracking step through. The bound must hold at every point (a
// wrong cell is a biased image), and the transport through them must not change.

#include <gtest/gtest.h>

#include <string>

#include "majorant_check.h"
#include "media/medium.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"
#include "scene/scene_desc.h"

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
