// Helpers for statistical render tests: render scene text in-process, image statistics.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "film/image.h"
#include "integrators/render_job.h"
#include "scene/scene_desc.h"

namespace ml::test {

inline RenderOutput render_text(const std::string& text, RenderOptions opt) {
    opt.progress = false;
    return render_scene(parse_scene_string(text, "."), opt);
}

struct ChannelStats {
    double mean = 0, stderr_of_mean = 0;
};

// Mean of one channel over the image and the standard error of that mean, treating pixels as
// independent samples (true for per-pixel sample sequences).
inline ChannelStats channel_stats(const Image& img, int c) {
    double s = 0, s2 = 0;
    size_t n = img.pixels.size();
    for (const RGB& p : img.pixels) {
        s += p[c];
        s2 += double(p[c]) * p[c];
    }
    ChannelStats st;
    st.mean = s / n;
    double var = std::max(0.0, s2 / n - st.mean * st.mean);
    st.stderr_of_mean = std::sqrt(var / (n - 1));
    return st;
}

// A scene lit from straight above by a distant light of radiance pi (an upward-facing diffuse
// surface shows its albedo), max depth 1, box filter: `view` holds its LookAt and Camera lines
// (the scene's lines 2 and 3), `world` what follows the light.
inline std::string lit_from_above(const std::string& view, int width, int height, int spp,
                                  const std::string& world) {
    return fmt::format(
        "\n{}\nFilm \"rgb\" \"integer xresolution\" [ {} ] \"integer yresolution\" [ {} ]\n"
        "Sampler \"independent\" \"integer pixelsamples\" [ {} ]\nPixelFilter \"box\"\n"
        "Integrator \"path\" \"integer maxdepth\" [ 1 ]\nWorldBegin\n"
        "LightSource \"distant\" \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
        "  \"rgb L\" [ 3.14159265 3.14159265 3.14159265 ]\n{}\n",
        view, width, height, spp, world);
}

// A camera inside a closed sphere of albedo `albedo` that emits Le from every point (two-sided):
// the radiance along every ray is Le (1 + albedo + albedo^2 + ...), cut at the path depth.
inline std::string furnace_scene(float albedo, float Le, int res = 24) {
    return fmt::format(R"(
LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" [ 60 ]
Film "rgb" "integer xresolution" [ {2} ] "integer yresolution" [ {2} ]
Sampler "independent"
PixelFilter "box"
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ {0} {0} {0} ] "bool twosided" true
  Material "diffuse" "rgb reflectance" [ {1} {1} {1} ]
  Shape "sphere" "float radius" [ 3 ]
AttributeEnd
)",
                       Le, albedo, res);
}

// Renders the furnace (albedo 0.5, Le 1) with `opt` and expects every channel's mean to be the
// geometric series cut at the path depth: Le (1 - a^(d+1)) / (1 - a), within 5 standard errors
// plus the tessellated sphere's tiny geometric error.
inline void expect_furnace(RenderOptions opt, int max_depth, float albedo = 0.5f, float Le = 1.f,
                           int res = 24) {
    opt.max_depth = max_depth;
    Image img = render_text(furnace_scene(albedo, Le, res), opt).image;
    double expected = Le * (1 - std::pow(double(albedo), max_depth + 1)) / (1 - albedo);
    for (int c = 0; c < 3; ++c) {
        ChannelStats st = channel_stats(img, c);
        EXPECT_NEAR(st.mean, expected, 5 * st.stderr_of_mean + 2e-3 * expected)
            << opt.integrator << " depth " << max_depth << " channel " << c;
    }
}

struct MeanDifference {
    double mean = 0, stderr_of_mean = 0;  // of a - b over the pixels
    double reference_mean = 0;            // of b
};

// The mean per-pixel difference of channel c between two renders of one scene and its standard
// error: the pixels' noise only, not the image's own variation, which the two share.
inline MeanDifference mean_difference(const Image& a, const Image& b, int c) {
    double n = double(a.pixels.size()), sd = 0, sd2 = 0, sb = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        double d = double(a.pixels[i][c]) - b.pixels[i][c];
        sd += d, sd2 += d * d, sb += b.pixels[i][c];
    }
    MeanDifference m;
    m.mean = sd / n;
    m.stderr_of_mean = std::sqrt(std::max(0.0, sd2 / n - m.mean * m.mean) / (n - 1));
    m.reference_mean = sb / n;
    return m;
}

// Channels in which two images of one size differ at all (0: the same bits), and channels of
// `a` above 0 (to tell a real comparison from two black images).
inline size_t differing_channels(const Image& a, const Image& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    size_t n = 0;
    for (size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i)
        for (int c = 0; c < 3; ++c) n += a.pixels[i][c] != b.pixels[i][c];
    return n;
}
inline size_t lit_channels(const Image& a) {
    size_t n = 0;
    for (const RGB& p : a.pixels)
        for (int c = 0; c < 3; ++c) n += p[c] > 0;
    return n;
}
// The largest relative difference of a channel (relative to a's, floor 1e-6 absolute).
inline double worst_relative_difference(const Image& a, const Image& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    double worst = 0;
    for (size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i)
        for (int c = 0; c < 3; ++c) {
            double x = a.pixels[i][c], y = b.pixels[i][c];
            worst = std::max(worst, std::abs(x - y) / std::max(std::abs(x), 1e-6));
        }
    return worst;
}

}  // namespace ml::test
