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
  "float conedeltaangle" [ 10 ])";

// The built-in Cornell box (its Gaussian pixel filter: splats are spread over it as camera
// samples are drawn from it), `extra` added to the world and its area light replaced by `light`
// if given.
inline std::string cornell_variant(const std::string& extra = "", const std::string& light = "") {
    std::string s = default_scene_text();
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
    Image a, b;               // the same integrator, two seeds
    std::vector<Image> more;  // further seeds (render_twice's `runs` > 2)
    std::vector<const Image*> all() const {
        std::vector<const Image*> v{&a, &b};
        for (const Image& m : more) v.push_back(&m);
        return v;
    }
};

inline TwoRenders render_twice(const std::string& text, const std::string& integrator, int spp,
                               int max_depth, int res, std::map<std::string, std::string> set = {},
                               int runs = 2) {
    TwoRenders r;
    for (int k = 0; k < runs; ++k) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = spp;
        opt.max_depth = max_depth;
        opt.width = opt.height = res;
        opt.seed = 11 + k;
        opt.sampler = "independent";
        opt.set = set;
        Image img = render_text(text, opt).image;
        if (k == 0)
            r.a = std::move(img);
        else if (k == 1)
            r.b = std::move(img);
        else
            r.more.push_back(std::move(img));
    }
    return r;
}

// Worst |z| over `block` x `block` block means (and the whole image) of the difference between
// two integrators' renders, each the mean of its runs (seeds). Each pixel's noise variance comes
// from the spread of its runs. Pixels are not independent where splats land (each is spread over
// the pixel filter, and pixels up to kSharedSplats apart, twice the Gaussian's radius of 1.5,
// share some): their covariances count too. Splats add with non-negative weights, so those
// covariances are not negative: the block's variance is at least the sum of its pixels'.
// Metropolis chains correlate pixels further apart (a chain stays in a caustic for many
// mutations): the spread of the runs' block means, valid whatever the correlations (with one
// degree of freedom fewer than runs), bounds the variance from below too.
constexpr int kSharedSplats = 3;

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
    // One integrator's runs over a region, channel c: the sum of the pixels' means, and
    // estimates of that sum's variance from the pixels' variances, their near covariances, and
    // the region sums' own spread.
    struct Region {
        double sum = 0, var = 0, cov = 0, spread = 0;
    };
    auto region = [&](const TwoRenders& r, int x0, int y0, int bw, int bh, int c) {
        std::vector<const Image*> runs = r.all();
        const double n = double(runs.size());
        auto mean = [&](int i, int j) {
            double m = 0;
            for (const Image* img : runs) m += img->at(i, j)[c];
            return m / n;
        };
        Region out;
        std::vector<double> run_sums(runs.size(), 0.0);
        for (int j = y0; j < y0 + bh; ++j)
            for (int i = x0; i < x0 + bw; ++i) {
                if (skip(i, j)) continue;
                double mi = mean(i, j);
                out.sum += mi;
                for (size_t k = 0; k < runs.size(); ++k) {
                    double ei = runs[k]->at(i, j)[c] - mi;
                    run_sums[k] += ei;
                    out.var += ei * ei / ((n - 1) * n);
                    for (int jj = std::max(y0, j - kSharedSplats);
                         jj <= std::min(y0 + bh - 1, j + kSharedSplats); ++jj)
                        for (int ii = std::max(x0, i - kSharedSplats);
                             ii <= std::min(x0 + bw - 1, i + kSharedSplats); ++ii)
                            if ((ii != i || jj != j) && !skip(ii, jj))
                                out.cov +=
                                    ei * (runs[k]->at(ii, jj)[c] - mean(ii, jj)) / ((n - 1) * n);
                }
            }
        for (double e : run_sums) out.spread += e * e / ((n - 1) * n);
        return out;
    };
    auto test_region = [&](int x0, int y0, int bw, int bh, double* worst, bool is_image) {
        int n = 0;
        for (int j = y0; j < y0 + bh; ++j)
            for (int i = x0; i < x0 + bw; ++i) n += !skip(i, j);
        if (n == 0) return;
        for (int c = 0; c < 3; ++c) {
            Region rx = region(x, x0, y0, bw, bh, c), ry = region(y, x0, y0, bw, bh, c);
            double var =
                std::max(rx.var + ry.var + std::max(0.0, rx.cov + ry.cov), rx.spread + ry.spread);
            double sd = std::sqrt(var) / n;
            double diff = (rx.sum - ry.sum) / n;
            if (sd == 0) {
                if (diff != 0) *worst = 1e9;
                continue;
            }
            double z = std::abs(diff) / sd;
            if (z > *worst) {
                *worst = z;
                if (!is_image)
                    out.worst = fmt::format("block ({}, {}) channel {}: {} vs {} (sd {})", x0, y0,
                                            c, rx.sum / n, ry.sum / n, sd);
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
    // Eight runs of 128 mutations per pixel: with two runs the block variance of MLT's
    // correlated noise has one degree of freedom and with four three, whose t tails pass 5
    // sigma in one block or another of one seed in six (a change of random streams showed it).
    expect_agreement(render_twice(scene, "mlt", 128, 4, 32, set, 8),
                     render_twice(scene, "path", 64, 4, 32), 16, what + " vs path, area light");
}

inline void expect_mlt_agrees_with_path_through_glass(const std::map<std::string, std::string>& set,
                                                      const std::string& what) {
    std::string scene = cornell_variant(glass_and_mirror());
    // Eight runs: their block means' spread is the variance estimate that holds for MLT's
    // correlated noise, and two give it one degree of freedom only (eight runs of 32
    // mutations per pixel detect a 20% error in the image mean; four of 64, 35%).
    expect_agreement(render_twice(scene, "mlt", 32, 5, 32, set, 8),
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
