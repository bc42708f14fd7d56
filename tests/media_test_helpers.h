// Helpers of the media tests (test_media.cpp, test_media_emission.cpp, test_subsurface.cpp):
// scene snippets, options, and the statistical comparisons they share.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>
#include <utility>

#include "integrators/render_job.h"
#include "render_helpers.h"

namespace ml::test {

// Within 4 standard errors of `expected`, and within `rel` of it (a loose check that catches a
// wrong answer whose noise is large too).
inline void expect_channel(const Image& img, int c, double expected, double rel) {
    const ChannelStats s = channel_stats(img, c);
    EXPECT_NEAR(s.mean, expected, 4 * s.stderr_of_mean + 1e-6)
        << "channel " << c << " (standard error " << s.stderr_of_mean << ")";
    EXPECT_NEAR(s.mean, expected, rel * expected) << "channel " << c;
}

// A medium "m" of the given type filling [-10, 10]^3 (a grid of 2^3 equal densities: pbrt-v4's
// grid falls to zero over the outer half cell, so the inner region is exactly `density`).
inline std::string medium(const std::string& type, const std::string& coefficients) {
    if (type == "homogeneous")
        return "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" " + coefficients + "\n";
    return "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" " + coefficients +
           " \"integer nx\" [ 2 ] \"integer ny\" [ 2 ] \"integer nz\" [ 2 ]"
           " \"float density\" [ 1 1 1 1 1 1 1 1 ] \"point3 p0\" [ -10 -10 -10 ]"
           " \"point3 p1\" [ 10 10 10 ]\n";
}

// A closed box [lo, hi] of outward-facing quads.
inline std::string box(const Vec3& lo, const Vec3& hi) {
    std::string p, idx;
    const Vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                       {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                       {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    for (const Vec3& v : c) p += fmt::format(" {} {} {}", v.x, v.y, v.z);
    // Counter-clockwise seen from outside: the winding's normal points out.
    const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    for (const auto& f : faces)
        idx += fmt::format(" {} {} {} {} {} {}", f[0], f[1], f[2], f[0], f[2], f[3]);
    return "Shape \"trianglemesh\" \"point3 P\" [" + p + " ] \"integer indices\" [" + idx + " ]\n";
}

// Each channel of `other` against `path`, pixel by pixel: within 4 standard errors of the
// pixels' differences and within `rel` of path's mean.
inline void expect_agrees_with_path(const Image& other, const Image& path, const std::string& who,
                                    double rel) {
    for (int c = 0; c < 3; ++c) {
        const MeanDifference d = mean_difference(other, path, c);
        EXPECT_NEAR(d.mean, 0, 4 * d.stderr_of_mean + 1e-6)
            << "channel " << c << ": " << who << " - path " << d.mean << " (standard error "
            << d.stderr_of_mean << ")";
        EXPECT_LT(std::abs(d.mean), rel * d.reference_mean) << "channel " << c;
    }
}

inline RenderOptions options(int spp) {
    RenderOptions opt;
    opt.spp = spp;
    opt.seed = 3;
    return opt;
}

// Each of `others` (integrator, samples per pixel) renders `scene` as `path` at 2048 spp does,
// pixel by pixel, per channel (expect_agrees_with_path, within 3%).
inline void expect_integrators_agree_with_path(
    const std::string& scene, std::initializer_list<std::pair<const char*, int>> others) {
    const Image path = render_text(scene, options(2048)).image;
    for (auto [integrator, spp] : others) {
        SCOPED_TRACE(integrator);
        RenderOptions opt = options(spp);
        opt.integrator = integrator;
        const Image other = render_text(scene, opt).image;
        expect_agrees_with_path(other, path, integrator, 0.03);
    }
}

inline std::string coloured_cloud(const std::string& type) {
    return "LookAt 0 2 -6  0 0.8 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
           "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 18 ]\n"
           "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 4 ]\n"
           "WorldBegin\n" +
           medium(type,
                  "\"rgb sigma_a\" [ 0.1 0.1 0.1 ] \"rgb sigma_s\" [ 0.3 0.8 1.5 ] "
                  "\"float g\" [ 0.6 ]") +
           "AttributeBegin\nTranslate 0 4 0\nAreaLightSource \"diffuse\" \"rgb L\" [ 20 20 20 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
           "  \"point3 P\" [ -0.6 0 -0.6  0.6 0 -0.6  0.6 0 0.6  -0.6 0 0.6 ]\nAttributeEnd\n"
           "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
           "  \"point3 P\" [ -5 0 -5  -5 0 5  5 0 5  5 0 -5 ]\n"
           "AttributeBegin\nMediumInterface \"m\" \"\"\nMaterial \"interface\"\n" +
           box(Vec3(-1, 0.01f, -1), Vec3(1, 2, 1)) + "AttributeEnd\n";
}

}  // namespace ml::test
