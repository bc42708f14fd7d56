// --seed reaches every random choice of the many-light integrators (issue 13, item 2): the
// points on area lights, the VPLs' light paths and the light tree's representatives follow the
// render's seed unless vpl.seed is given, so renders with different seeds are independent (the
// equal-time bench's "three seeds" share no VPL set), and a seed gives the same image at any
// thread count.
#include <gtest/gtest.h>

#include "integrators/vpl/vpl.h"
#include "render/settings.h"
#include "render_helpers.h"
#include "scene/default_scene.h"
#include "scene/scene.h"

using namespace ml;

namespace {

ManyLightSettings settings_with(std::map<std::string, std::string> set) {
    return ManyLightSettings::read(Settings("lightcuts", nullptr, std::move(set)));
}

RenderOptions options(const std::string& integrator, uint64_t seed, int threads = 2) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = 4;
    opt.width = 16;
    opt.height = 16;
    opt.seed = seed;
    opt.threads = threads;
    opt.set["vpl.count"] = "300";
    opt.set["lights.area_count"] = "64";
    if (integrator == "mdlightcuts") opt.set["mdlightcuts.samples"] = "4";
    return opt;
}

Image render(const RenderOptions& opt) {
    return test::render_text(default_scene_text(), opt).image;
}

bool identical(const Image& a, const Image& b) {
    if (a.pixels.size() != b.pixels.size()) return false;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        if (!(a.pixels[i] == b.pixels[i])) return false;
    return true;
}

bool same_lights(const PointLightSet& a, const PointLightSet& b) {
    if (a.lights.size() != b.lights.size()) return false;
    for (size_t i = 0; i < a.lights.size(); ++i)
        if (!(a.lights[i].p == b.lights[i].p) || !(a.lights[i].intensity == b.lights[i].intensity))
            return false;
    return true;
}

}  // namespace

TEST(ManyLightSeeds, TheRenderSeedIsTheLightsSeedUnlessVplSeedIsGiven) {
    ManyLightSettings m = settings_with({});
    m.use_render_seed(7);
    EXPECT_EQ(m.lights.seed, 7u);
    m.use_render_seed(8);
    EXPECT_EQ(m.lights.seed, 8u);
    ManyLightSettings given = settings_with({{"vpl.seed", "3"}});
    given.use_render_seed(7);
    EXPECT_EQ(given.lights.seed, 3u);
    ManyLightSettings follow = settings_with({{"vpl.seed", "-1"}});
    follow.use_render_seed(7);
    EXPECT_EQ(follow.lights.seed, 7u);
    EXPECT_THROW(settings_with({{"vpl.seed", "-2"}}), UsageError);
}

// Two lights seeds give different point lights on the area light and different VPLs; one seed
// gives the same set.
TEST(ManyLightSeeds, TwoSeedsGiveDifferentVplSets) {
    Scene scene(parse_scene_string(default_scene_text(), "."));
    PointLightOptions o;
    o.area_count = 64;
    o.vpl_count = 300;
    auto build = [&](uint64_t seed) {
        o.seed = seed;
        return build_point_light_set(scene, o);
    };
    PointLightSet one = build(1), again = build(1), two = build(2);
    EXPECT_TRUE(same_lights(one, again));
    ASSERT_GT(one.vpls, 0u);
    ASSERT_GT(two.vpls, 0u);
    size_t emitters = one.lights.size() - one.vpls;
    EXPECT_NE(one.lights[0].p, two.lights[0].p);                // a point on the area light
    EXPECT_NE(one.lights[emitters].p, two.lights[emitters].p);  // the first VPL
}

// Through the whole render: with the camera's samples fixed (--seed 1), leaving vpl.seed out
// gives exactly vpl.seed=1's image, and vpl.seed=2 another; so --seed 1 and --seed 2 shade with
// different point lights and representatives (TwoSeedsGiveDifferentVplSets).
TEST(ManyLightSeeds, TheRenderSeedReachesTheLightsAndRepresentatives) {
    for (const char* integrator : {"vpl", "lightcuts", "mdlightcuts", "stochasticlightcuts"}) {
        RenderOptions opt = options(integrator, 1);
        Image by_render_seed = render(opt);
        opt.set["vpl.seed"] = "1";
        EXPECT_TRUE(identical(by_render_seed, render(opt))) << integrator;
        opt.set["vpl.seed"] = "2";
        EXPECT_FALSE(identical(by_render_seed, render(opt))) << integrator;
    }
    // The representatives alone: 64 point lights (no VPLs, nothing drawn for the lights) give
    // another lightcuts image when only the tree's seed changes.
    std::string lights = R"(LookAt 0 3 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
WorldBegin
Material "diffuse"
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ] "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ]
)";
    for (int i = 0; i < 64; ++i)
        lights += fmt::format(
            "LightSource \"point\" \"rgb I\" [ 0.1 0.1 0.1 ] \"point3 from\" [ {} 1 {} ]\n",
            -2 + (i % 8) * 0.5, -2 + (i / 8) * 0.5);
    RenderOptions opt = options("lightcuts", 1);
    opt.set["vpl.count"] = "0";
    opt.set.erase("lights.area_count");
    opt.set["vpl.seed"] = "1";
    Image one = test::render_text(lights, opt).image;
    opt.set["vpl.seed"] = "2";
    EXPECT_FALSE(identical(one, test::render_text(lights, opt).image));
}

TEST(ManyLightSeeds, OneSeedGivesTheSameImageAtOneAndTwoThreads) {
    for (const char* integrator : {"vpl", "lightcuts", "mdlightcuts", "stochasticlightcuts"}) {
        Image one = render(options(integrator, 4, 1));
        Image two = render(options(integrator, 4, 2));
        EXPECT_TRUE(identical(one, two)) << integrator;
        EXPECT_FALSE(identical(one, render(options(integrator, 5, 2)))) << integrator;
    }
}
