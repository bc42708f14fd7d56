// The igi integrator: interleaved splitting and gathering, the discontinuity filter, and igi
// against the brute-force vpl integrator on the same VPLs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "integrators/igi/interleave.h"
#include "render_helpers.h"
#include "vpl_test_scenes.h"

namespace ml {
namespace {

TEST(IgiInterleave, SplitAndGatherAreInverseBijections) {
    for (int width : {1, 2, 3, 7, 16, 33})
        for (int height : {1, 4, 5, 9})
            for (int n : {1, 2, 3, 4, 5, 8, 40})
                for (int m : {1, 2, 3, 6}) {
                    InterleavedLayout layout(width, height, n, m);
                    std::vector<int> image(size_t(width) * height);
                    for (size_t i = 0; i < image.size(); ++i) image[i] = int(i);
                    std::vector<int> split = layout.split(image);
                    // A permutation: every pixel lands once.
                    std::vector<int> seen(image.size(), 0);
                    for (int v : split) ++seen[v];
                    for (int s : seen) ASSERT_EQ(s, 1) << width << "x" << height << " " << n << m;
                    EXPECT_EQ(layout.gather(split), image);
                    for (int y = 0; y < height; ++y)
                        for (int x = 0; x < width; ++x) {
                            Point2i s = layout.to_split({x, y});
                            ASSERT_TRUE(layout.to_image(s) == (Point2i{x, y}));
                            // Pixel (x, y) is at (x / n, y / m) inside its sub-buffer, and the
                            // sub-buffer's pixels form one block of the split buffer.
                            Point2i origin = layout.to_split({x % n, y % m});
                            EXPECT_EQ(s.x - origin.x, x / n);
                            EXPECT_EQ(s.y - origin.y, y / m);
                            EXPECT_EQ(layout.sub_buffer({x, y}), (y % m) * n + x % n);
                        }
                }
}

// A 40x30 G-buffer with a depth edge at x = 20 (depth 1 | 2) and a normal edge at y = 15
// (normal +z above, tilted 60 degrees below); each region's values lie in a range of its own.
struct Quadrants {
    static constexpr int w = 40, h = 30;
    std::vector<GBufferTexel> gbuffer;
    std::vector<RGB> image;
    static int region(int x, int y) { return (x >= 20 ? 1 : 0) + (y >= 15 ? 2 : 0); }
    Quadrants() : gbuffer(w * h), image(w * h) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                GBufferTexel& t = gbuffer[y * w + x];
                t.valid = true;
                t.depth = x >= 20 ? 2.f : 1.f;
                t.n = y >= 15 ? Vec3(0, std::sin(1.0472f), std::cos(1.0472f)) : Vec3(0, 0, 1);
                // On planes z = depth (above) and, below, tilted 60 degrees about x through the
                // line y = 15 (pixel pitch 0.01), so neighbours within a region are continuous.
                float px = 0.01f * float(x), py = 0.01f * float(y);
                float z = y >= 15 ? t.depth - std::tan(1.0472f) * (py - 0.15f) : t.depth;
                t.p = Vec3(px, py, z);
                float v = 10.f * float(region(x, y)) + u(rng);  // region r: [10 r, 10 r + 1)
                image[y * w + x] = RGB(v, v, v);
            }
    }
};

TEST(IgiFilter, NeverBlursAcrossDepthOrNormalEdges) {
    Quadrants q;
    DiscontinuityThresholds t;  // 5% depth, 25 degrees
    for (int size : {2, 3, 4, 5, 8, 19}) {
        std::vector<RGB> out = discontinuity_filter(q.image, q.gbuffer, q.w, q.h, size, size, t);
        double var_in = 0, var_out = 0;
        for (int y = 0; y < q.h; ++y)
            for (int x = 0; x < q.w; ++x) {
                float lo = 10.f * float(Quadrants::region(x, y)), v = out[y * q.w + x].r;
                ASSERT_GE(v, lo) << "size " << size << " at " << x << "," << y;
                ASSERT_LT(v, lo + 1.f) << "size " << size << " at " << x << "," << y;
                var_in += std::pow(q.image[y * q.w + x].r - lo - 0.5, 2);
                var_out += std::pow(v - lo - 0.5, 2);
            }
        // It does blur within the regions: the noise's variance drops.
        EXPECT_LT(var_out, 0.5 * var_in) << "size " << size;
    }
}

TEST(IgiFilter, BlursWithinThresholdsAndKeepsInvalidPixels) {
    Quadrants q;
    DiscontinuityThresholds wide;
    wide.depth = 1.5f;   // depth 1 and 2 are continuous
    wide.normal = 70.f;  // so are the two normals
    std::vector<RGB> out = discontinuity_filter(q.image, q.gbuffer, q.w, q.h, 3, 3, wide);
    // Pixel (19, 14) touches all four regions: its 3x3 mean mixes them.
    float v = out[14 * q.w + 19].r;
    EXPECT_GT(v, 5.f);
    EXPECT_LT(v, 25.f);
    // An invalid pixel keeps its value and is never averaged in.
    q.gbuffer[5 * q.w + 5].valid = false;
    q.image[5 * q.w + 5] = RGB(1e6f);
    out = discontinuity_filter(q.image, q.gbuffer, q.w, q.h, 5, 4, DiscontinuityThresholds{});
    EXPECT_EQ(out[5 * q.w + 5].r, 1e6f);
    EXPECT_LT(out[5 * q.w + 6].r, 1.f);
    // A 1x1 window: unchanged.
    EXPECT_EQ(discontinuity_filter(q.image, q.gbuffer, q.w, q.h, 1, 1, DiscontinuityThresholds{}),
              q.image);
}

std::string igi_test_scene() {
    return R"(LookAt 0 1.2 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 27 ] "integer yresolution" [ 19 ]
Sampler "independent"
WorldBegin
)" + vpl_test::mixed_box();
}

RenderOptions igi_options(const std::string& integrator, int spp) {
    RenderOptions o;
    o.integrator = integrator;
    o.spp = spp;
    o.threads = 2;
    o.set["vpl.count"] = "300";
    // vpl on igi's VPLs: one set per render, clamped and diffuse-only as igi's are.
    if (integrator == std::string("vpl")) {
        o.set["vpl.sets"] = "one";
        o.set["vpl.clamp"] = "0.2";
        o.set["vpl.glossy"] = "diffuse";
    }
    return o;
}

TEST(Igi, OneByOneWithoutFilterIsVplOnTheSameVpls) {
    for (const char* direct : {"sample", "points"}) {
        RenderOptions v = igi_options("vpl", 2), g = igi_options("igi", 2);
        v.set["lights.direct"] = g.set["lights.direct"] = direct;
        g.set["igi.interleave"] = "1x1";
        g.set["igi.filter"] = "0";
        for (const char* packets : {"true", "false"}) {
            g.set["igi.packets"] = packets;
            RenderOutput a = test::render_text(igi_test_scene(), v);
            RenderOutput b = test::render_text(igi_test_scene(), g);
            ASSERT_EQ(a.figures.vpls, b.figures.vpls);
            double mean = 0;
            for (const RGB& p : a.image.pixels) mean += p.r + p.g + p.b;
            mean /= 3.0 * a.image.pixels.size();
            ASSERT_GT(mean, 0.01);
            // The same samples and shadow rays: equal up to the order of float additions.
            for (size_t i = 0; i < a.image.pixels.size(); ++i)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(b.image.pixels[i][c], a.image.pixels[i][c],
                                1e-5 * (a.image.pixels[i][c] + mean))
                        << direct << " packets " << packets << " pixel " << i;
        }
    }
}

TEST(Igi, InterleavedImageAveragesToTheFullSum) {
    // Each sub-buffer's VPLs, scaled by their share, estimate every VPL's light: over the image
    // the interleaved render's mean meets vpl's (the same VPLs and gather points) within the
    // spread of the subsets' estimates.
    RenderOptions v = igi_options("vpl", 1), g = igi_options("igi", 1);
    v.set["vpl.count"] = g.set["vpl.count"] = "2000";
    g.set["igi.interleave"] = "3x2";
    g.set["igi.filter"] = "1";
    RenderOutput a = test::render_text(igi_test_scene(), v);
    RenderOutput b = test::render_text(igi_test_scene(), g);
    for (int c = 0; c < 3; ++c) {
        test::ChannelStats sa = test::channel_stats(a.image, c),
                           sb = test::channel_stats(b.image, c);
        EXPECT_NEAR(sb.mean, sa.mean, 0.03 * sa.mean) << "channel " << c;
    }
}

TEST(Igi, DeterministicForASeedAtAnyThreadCount) {
    RenderOptions a = igi_options("igi", 1), b = a;
    a.threads = 1;
    RenderOutput x = test::render_text(igi_test_scene(), a);
    RenderOutput y = test::render_text(igi_test_scene(), b);
    EXPECT_EQ(x.image.pixels, y.image.pixels);
    b.seed = 5;
    RenderOutput z = test::render_text(igi_test_scene(), b);
    EXPECT_NE(x.image.pixels, z.image.pixels);
}

TEST(Igi, BadSettingsAreUsageErrors) {
    for (auto [key, value] :
         std::vector<std::pair<std::string, std::string>>{{"igi.interleave", "4"},
                                                          {"igi.interleave", "0x2"},
                                                          {"igi.interleave", "4x4x"},
                                                          {"igi.filter", "-1"},
                                                          {"igi.normal_threshold", "200"},
                                                          {"igi.vpls", "-3"}}) {
        RenderOptions o = igi_options("igi", 1);
        o.set.erase("vpl.count");
        o.set[key] = value;
        EXPECT_THROW(test::render_text(igi_test_scene(), o), UsageError) << key << "=" << value;
    }
    RenderOptions both = igi_options("igi", 1);
    both.set["igi.vpls"] = "10";
    EXPECT_THROW(test::render_text(igi_test_scene(), both), UsageError);
}

}  // namespace
}  // namespace ml

namespace ml {
namespace {

// --look-at with the scene's own LookAt renders the scene's image, with or without a
// `Scale -1 1 1` before it (the viewer's views keep the scene's handedness).
TEST(LookAt, TheScenesOwnLookAtRendersTheScenesImage) {
    for (const char* prefix : {"", "Scale -1 1 1\n"}) {
        std::string text = std::string(prefix) + R"(LookAt 0.3 1.2 -4  0 0.5 0.2  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 20 ] "integer yresolution" [ 14 ]
Sampler "independent"
WorldBegin
)" + vpl_test::mixed_box();
        RenderOptions o;
        o.integrator = "direct";
        o.spp = 2;
        RenderOutput a = test::render_text(text, o);
        o.look_at = std::array<float, 9>{0.3f, 1.2f, -4, 0, 0.5f, 0.2f, 0, 1, 0};
        RenderOutput b = test::render_text(text, o);
        double diff = 0, sum = 0;
        for (size_t i = 0; i < a.image.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                diff += std::abs(a.image.pixels[i][c] - b.image.pixels[i][c]);
                sum += a.image.pixels[i][c];
            }
        EXPECT_GT(sum, 0) << prefix;
        EXPECT_LT(diff, 1e-4 * sum) << "with prefix \"" << prefix << "\"";
        // A different view gives a different image.
        o.look_at = std::array<float, 9>{-0.3f, 1.2f, -4, 0, 0.5f, 0.2f, 0, 1, 0};
        EXPECT_NE(test::render_text(text, o).image.pixels, a.image.pixels);
        o.look_at = std::array<float, 9>{0, 0, 0, 0, 0, 0, 0, 1, 0};
        EXPECT_THROW(test::render_text(text, o), UsageError);
    }
}

}  // namespace
}  // namespace ml
