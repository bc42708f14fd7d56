// Helpers for the light tracing and BDPT tests: Cornell-box variants, and agreement between two
// integrators with a tolerance from the renders' own noise.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>

#include "bidir/path_vertex.h"
#include "camera/camera.h"
#include "lights/light_sampler.h"
#include "render_helpers.h"
#include "scene/default_scene.h"

namespace ml::test {

// Delta lights for the Cornell box (instead of its area light).
inline const std::string kCornellPointLight = R"(LightSource "point" "rgb I" [ 60000 50000 30000 ]
  "point3 from" [ 278 500 279 ])";
inline const std::string kCornellSpotLight = R"(LightSource "spot" "rgb I" [ 150000 120000 80000 ]
  "point3 from" [ 278 540 279 ] "point3 to" [ 278 0 279 ] "float coneangle" [ 40 ]
  "float conedelta" [ 10 ])";

// The built-in Cornell box with a box pixel filter (splats land in one pixel, like the box
// filter's samples), `extra` added to the world and its area light replaced by `light` if given.
inline std::string cornell_variant(const std::string& extra = "", const std::string& light = "") {
    std::string s = default_scene_text();
    auto replace = [&](const std::string& from, const std::string& to) {
        size_t at = s.find(from);
        if (at != std::string::npos) s.replace(at, from.size(), to);
    };
    replace("PixelFilter \"gaussian\"", "PixelFilter \"box\"");
    size_t light_at = s.find("# The light, a hair below the ceiling");
    std::string tail = s.substr(light_at);
    s = s.substr(0, light_at) + extra + "\n" + (light.empty() ? tail : light + "\n");
    return s;
}

// A glass sphere over the short block and a mirror sphere over the tall one.
inline std::string glass_and_mirror() {
    return R"(
AttributeBegin
  Material "dielectric" "float eta" [ 1.5 ]
  Translate 186 245 169
  Shape "sphere" "float radius" [ 80 ]
AttributeEnd
AttributeBegin
  Material "conductor" "float roughness" [ 0 ]
  Translate 368 400 351
  Shape "sphere" "float radius" [ 70 ]
AttributeEnd
)";
}

struct TwoRenders {
    Image a, b;  // the same integrator, two seeds
};

inline TwoRenders render_twice(const std::string& text, const std::string& integrator, int spp,
                               int max_depth, int res,
                               std::map<std::string, std::string> set = {}) {
    TwoRenders r;
    for (int k = 0; k < 2; ++k) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = spp;
        opt.max_depth = max_depth;
        opt.width = opt.height = res;
        opt.seed = 11 + k;
        opt.sampler = "independent";
        opt.set = set;
        (k == 0 ? r.a : r.b) = render_text(text, opt).image;
    }
    return r;
}

// Worst |z| over `block` x `block` block means (and the whole image) of the difference between
// two integrators' renders. Each pixel's noise variance comes from its two renders:
// E[(x1 - x2)^2] / 4 is the variance of their mean.
struct Agreement {
    double worst_block_z = 0, worst_image_z = 0;
    std::string worst;
};

// `skip_block(x0, y0)`, if given, leaves blocks out (of the image's mean too).
inline Agreement agreement(const TwoRenders& x, const TwoRenders& y, int block,
                           const std::function<bool(int, int)>& skip_block = {}) {
    Agreement out;
    int w = x.a.width, h = x.a.height;
    auto skip = [&](int i, int j) {
        return skip_block && skip_block(i / block * block, j / block * block);
    };
    auto test_region = [&](int x0, int y0, int bw, int bh, double* worst, bool is_image) {
        for (int c = 0; c < 3; ++c) {
            double mx = 0, my = 0, vx = 0, vy = 0;
            int n = 0;
            for (int j = y0; j < y0 + bh; ++j)
                for (int i = x0; i < x0 + bw; ++i) {
                    if (skip(i, j)) continue;
                    ++n;
                    double x1 = x.a.at(i, j)[c], x2 = x.b.at(i, j)[c];
                    double y1 = y.a.at(i, j)[c], y2 = y.b.at(i, j)[c];
                    mx += 0.5 * (x1 + x2);
                    my += 0.5 * (y1 + y2);
                    vx += 0.25 * (x1 - x2) * (x1 - x2);
                    vy += 0.25 * (y1 - y2) * (y1 - y2);
                }
            if (n == 0) continue;
            double sd = std::sqrt(vx + vy) / n;
            double diff = (mx - my) / n;
            if (sd == 0) {
                if (diff != 0) *worst = 1e9;
                continue;
            }
            double z = std::abs(diff) / sd;
            if (z > *worst) {
                *worst = z;
                if (!is_image)
                    out.worst = fmt::format("block ({}, {}) channel {}: {} vs {} (sd {})", x0, y0,
                                            c, mx / n, my / n, sd);
            }
        }
    };
    for (int y0 = 0; y0 < h; y0 += block)
        for (int x0 = 0; x0 < w; x0 += block)
            test_region(x0, y0, block, block, &out.worst_block_z, false);
    test_region(0, 0, w, h, &out.worst_image_z, true);
    return out;
}

// Blocks: at most 5 standard deviations (about 1 in 10^6 per block and channel for normal
// noise); the image mean: 4.
inline void expect_agreement(const TwoRenders& x, const TwoRenders& y, int block,
                             const std::string& what,
                             const std::function<bool(int, int)>& skip_block = {}) {
    Agreement a = agreement(x, y, block, skip_block);
    EXPECT_LT(a.worst_block_z, 5.0) << what << ": worst " << a.worst;
    EXPECT_LT(a.worst_image_z, 4.0) << what;
}

// The scene, camera and light sampler of a scene text, for direct use of the BDPT pieces and the
// mutations built on them.
struct Bench {
    std::unique_ptr<PerspectiveCamera> camera;
    std::unique_ptr<Scene> scene;
    std::unique_ptr<LightSampler> lights;
    std::unique_ptr<BdptScene> ctx;
    explicit Bench(const std::string& text, int res) {
        SceneDesc desc = parse_scene_string(text, ".");
        camera = std::make_unique<PerspectiveCamera>(desc.camera.params,
                                                     desc.world_to_camera.inverse(), res, res);
        scene = std::make_unique<Scene>(std::move(desc));
        lights = std::make_unique<LightSampler>("power", scene->lights());
        ctx = std::make_unique<BdptScene>(*scene, *camera, *lights);
    }
};

// The checks every configuration of `mlt` answers to, `set` its settings and `what` its name.
// The white furnace at depth 3: Le (1 + a + a^2 + a^3); the two seeds' spread sets the tolerance
// (the image's scale b comes from the bootstrap, whose noise moves every pixel together).
inline void expect_mlt_furnace(const std::map<std::string, std::string>& set) {
    auto r = render_twice(furnace_scene(0.5f, 1.f, 16), "mlt", 64, 3, 16, set);
    double expected = 1.875;
    for (int c = 0; c < 3; ++c) {
        double m1 = channel_stats(r.a, c).mean, m2 = channel_stats(r.b, c).mean;
        double sd = std::abs(m1 - m2) / std::sqrt(2.0);
        EXPECT_NEAR(0.5 * (m1 + m2), expected, 5 * sd + 0.01 * expected) << "channel " << c;
    }
}

inline void expect_mlt_agrees_with_path_on_cornell(const std::map<std::string, std::string>& set,
                                                   const std::string& what) {
    std::string scene = cornell_variant();
    expect_agreement(render_twice(scene, "mlt", 64, 4, 32, set),
                     render_twice(scene, "path", 64, 4, 32), 16, what + " vs path, area light");
}

inline void expect_mlt_agrees_with_path_through_glass(const std::map<std::string, std::string>& set,
                                                      const std::string& what) {
    std::string scene = cornell_variant(glass_and_mirror());
    expect_agreement(render_twice(scene, "mlt", 128, 5, 32, set),
                     render_twice(scene, "path", 256, 5, 32), 16,
                     what + " vs path, glass and mirror");
}

// Path tracing cannot find these caustics; BDPT (tested against light tracing) can.
inline void expect_mlt_agrees_with_bdpt_on_caustics(const std::map<std::string, std::string>& set,
                                                    const std::string& what) {
    std::string scene = cornell_variant(glass_and_mirror(), kCornellPointLight);
    expect_agreement(render_twice(scene, "mlt", 128, 4, 32, set),
                     render_twice(scene, "bdpt", 64, 4, 32), 16,
                     what + " vs bdpt, point light, glass and mirror");
}

}  // namespace ml::test
