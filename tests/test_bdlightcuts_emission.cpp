// bdlightcuts' last split (the emitter met by the eye path) by light samples as well as BSDF
// samples, weighed by MIS (`bdlightcuts.emission=mis`, the default), and the remainder's paths per
// continued eye path (`bdlightcuts.rest_paths`): both estimate the same split-weighted sum as
// before, so they agree with `path`; the light samples lower the variance where clamping leaves
// most of a close light to the last split.
#include <gtest/gtest.h>

#include "bidir_test_helpers.h"
#include "core/error.h"
#include "render_helpers.h"

using namespace ml;
using Set = std::map<std::string, std::string>;

namespace {

// A small bright light 0.35 above a diffuse floor and a rough conductor beside it: at that range
// the clamping weight (C_clamp 0.01) leaves most of the light's direct contribution to the last
// split, where BSDF samples alone find the small light rarely.
const char* kCloseLight = R"(
LookAt 0 1.6 1.6  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
Sampler "independent"
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 40 36 30 ]
  Shape "trianglemesh" "point3 P" [ -0.1 0.35 -0.1  0.1 0.35 -0.1  0.1 0.35 0.1  -0.1 0.35 0.1 ]
    "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
Shape "trianglemesh" "point3 P" [ -2 0 -2  0 0 -2  0 0 2  -2 0 2 ] "integer indices" [ 0 2 1 0 3 2 ]
Material "conductor" "float roughness" [ 0.2 ] "rgb reflectance" [ 0.8 0.8 0.8 ]
Shape "trianglemesh" "point3 P" [ 0 0 -2  2 0 -2  2 0 2  0 0 2 ] "integer indices" [ 0 2 1 0 3 2 ]
Material "diffuse" "rgb reflectance" [ 0.4 0.5 0.6 ]
Shape "trianglemesh" "point3 P" [ -2 0 -1  2 0 -1  2 2 -1  -2 2 -1 ] "integer indices" [ 0 1 2 0 2 3 ]
)";

// A wide light 2.2 above a diffuse floor and a glossy conductor beside it, with a point light
// near the floor: far from the wide light the first split takes most of its direct light, and on
// the glossy floor the BSDF sample finds it more often than a light sample does (MIS gives it
// most of the weight there). Near the point light the clamping weight is far below 1, and no
// other split can take a path that ends at a point light.
const char* kWideLight = R"(
LookAt 0 1.6 1.6  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
Sampler "independent"
WorldBegin
LightSource "point" "point3 from" [ 0.8 0.9 0.3 ] "rgb I" [ 0.3 0.3 0.4 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1.2 1.1 1.0 ] "bool twosided" true
  Shape "trianglemesh" "point3 P" [ -1.5 2.2 -1.5  1.5 2.2 -1.5  1.5 2.2 1.5  -1.5 2.2 1.5 ]
    "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
Shape "trianglemesh" "point3 P" [ -2 0 -2  0 0 -2  0 0 2  -2 0 2 ] "integer indices" [ 0 2 1 0 3 2 ]
Material "conductor" "float roughness" [ 0.05 ] "rgb reflectance" [ 0.8 0.8 0.8 ]
Shape "trianglemesh" "point3 P" [ 0 0 -2  2 0 -2  2 0 2  0 0 2 ] "integer indices" [ 0 2 1 0 3 2 ]
)";

Set bdlc(const Set& extra) {
    Set s = {{"vpl.count", "1500"}, {"bdlightcuts.samples", "8"}, {"bdlightcuts.error", "0.02"}};
    for (const auto& [k, v] : extra) s[k] = v;
    return s;
}

// The mean over pixels and channels of the per-pixel variance across the runs.
double pixel_variance(const test::TwoRenders& r) {
    std::vector<const Image*> all = r.all();
    const size_t n = all.size(), pixels = all[0]->pixels.size();
    double sum = 0;
    for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) {
            double m = 0, v = 0;
            for (const Image* img : all) m += img->pixels[i][c];
            m /= double(n);
            for (const Image* img : all) v += (img->pixels[i][c] - m) * (img->pixels[i][c] - m);
            sum += v / double(n - 1);
        }
    return sum / double(pixels * 3);
}

void expect_usage_error(const Set& set, const std::string& message) {
    RenderOptions opt;
    opt.integrator = "bdlightcuts";
    opt.spp = 1;
    opt.width = opt.height = 8;
    opt.set = bdlc(set);
    try {
        test::render_text(kCloseLight, opt);
        ADD_FAILURE() << "accepted: " << set.begin()->first << "=" << set.begin()->second;
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(BdLightcutsEmission, LightSamplesAgreeWithPathAndLowerTheVariance) {
    auto ref = test::render_twice(kCloseLight, "path", 512, 4, 16, {}, 4);
    auto mis = test::render_twice(kCloseLight, "bdlightcuts", 32, 4, 16,
                                  bdlc({{"bdlightcuts.emission", "mis"}}), 4);
    auto hit = test::render_twice(kCloseLight, "bdlightcuts", 32, 4, 16,
                                  bdlc({{"bdlightcuts.emission", "hit"}}), 4);
    // At the diffuse floor's VSPs with lights.direct_mis=glossy the emitters' split takes its
    // light sample alone, and the last split its BSDF samples alone (most of the close light).
    auto alone = test::render_twice(kCloseLight, "bdlightcuts", 32, 4, 16,
                                    bdlc({{"lights.direct_mis", "glossy"}}), 4);
    test::expect_agreement(mis, ref, 8, "emission=mis");
    test::expect_agreement(hit, ref, 8, "emission=hit");
    test::expect_agreement(alone, ref, 8, "emission=mis direct_mis=glossy");
    // Where the last split carries the close light, light samples find it every time.
    EXPECT_LT(pixel_variance(mis), 0.7 * pixel_variance(hit))
        << "mis " << pixel_variance(mis) << ", hit " << pixel_variance(hit);
}

TEST(BdLightcutsEmission, SeveralBsdfSamplesAtGlossyVerticesAgreeWithPath) {
    // bdlightcuts.emission_samples: at the rough conductor's eye vertices, four BSDF samples
    // find the emission (each counting a quarter, MIS by the counts against the light sample),
    // the eye path going on along one. On the diffuse floor one, as by default.
    auto ref = test::render_twice(kCloseLight, "path", 512, 4, 16, {}, 4);
    auto one = test::render_twice(kCloseLight, "bdlightcuts", 32, 4, 16, bdlc({}), 4);
    auto four = test::render_twice(kCloseLight, "bdlightcuts", 32, 4, 16,
                                   bdlc({{"bdlightcuts.emission_samples", "4"}}), 4);
    test::expect_agreement(four, ref, 8, "emission_samples=4");
    // The glossy reflection of the small light, which the light sample finds rarely, is
    // found four times as often.
    EXPECT_LT(pixel_variance(four), pixel_variance(one))
        << "four " << pixel_variance(four) << ", one " << pixel_variance(one);
}

TEST(BdLightcutsEmission, SeveralRemainderPathsAgreeWithPath) {
    // At eye-path length 1 the remainder takes what the clamped first split leaves of every
    // longer path; three paths per continued eye path average to the same sum.
    const Set set = {{"bdlightcuts.eye_length", "1"}, {"bdlightcuts.rest_paths", "3"}};
    auto ref = test::render_twice(kCloseLight, "path", 512, 4, 16, {}, 4);
    auto three = test::render_twice(kCloseLight, "bdlightcuts", 32, 4, 16, bdlc(set), 4);
    test::expect_agreement(three, ref, 8, "rest_paths=3");
}

TEST(BdLightcutsEmission, EmittersAsPointsOrByLightSamplesAgreeWithPath) {
    // lights.direct=points (the emitters' points in the cut): the point light's pairs take no
    // clamping (before session 14 its clamped part was lost: 30% dark beside it).
    // lights.direct=sample (the default): the split joining a VSP to an area light by a light
    // sample at the VSP, weighed by MIS against the eye path's BSDF sample (or alone at diffuse
    // VSPs with lights.direct_mis=glossy), in place of the emitters' points in the cut; a point
    // light stays a point of the cut. With emission=mis (the default) the last split takes light
    // samples too: with points, its own; with sample, the emitters' split's, which carries both
    // weights where it is weighed by MIS (not at diffuse VSPs with direct_mis=glossy).
    const std::string scene = kWideLight;
    auto ref = test::render_twice(scene, "path", 512, 4, 16, {}, 4);
    auto render = [&](const Set& s) {
        return test::render_twice(scene, "bdlightcuts", 32, 4, 16, bdlc(s), 4);
    };
    auto points_hit = render({{"lights.direct", "points"}, {"bdlightcuts.emission", "hit"}});
    auto points_mis = render({{"lights.direct", "points"}});
    auto sample_hit = render({{"lights.direct", "sample"}, {"bdlightcuts.emission", "hit"}});
    auto sample_mis = render({});
    auto alone = render({{"lights.direct_mis", "glossy"}});
    test::expect_agreement(points_hit, ref, 8, "direct=points emission=hit");
    test::expect_agreement(points_mis, ref, 8, "direct=points emission=mis");
    test::expect_agreement(sample_hit, ref, 8, "direct=sample emission=hit");
    test::expect_agreement(sample_mis, ref, 8, "direct=sample emission=mis");
    test::expect_agreement(alone, ref, 8, "direct=sample emission=mis direct_mis=glossy");
}

TEST(BdLightcutsEmission, InfiniteLightByLightSamplesAgreesWithPath) {
    // An infinite light's split by light samples (D = 0 there: no clamping) and the escaped eye
    // path's share of it, with the defaults (lights.direct=sample).
    std::string scene = kWideLight;
    const std::string world = "WorldBegin\n";
    scene.insert(scene.find(world) + world.size(),
                 "LightSource \"infinite\" \"rgb L\" [ 0.2 0.25 0.3 ]\n");
    auto ref = test::render_twice(scene, "path", 512, 4, 16, {}, 4);
    auto sample = test::render_twice(scene, "bdlightcuts", 32, 4, 16, bdlc({}), 4);
    // A uniform infinite light leaves MIS's light samples nothing (their density is 0 where BSDF
    // samples do well); with lights.direct_mis=glossy, diffuse VSPs take it by light samples alone.
    auto alone = test::render_twice(scene, "bdlightcuts", 32, 4, 16,
                                    bdlc({{"lights.direct_mis", "glossy"}}), 4);
    test::expect_agreement(sample, ref, 8, "infinite light, direct=sample");
    test::expect_agreement(alone, ref, 8, "infinite light, direct_mis=glossy");
}

TEST(BdLightcutsEmission, SettingsTakeOnlyWhatTheyExpect) {
    expect_usage_error({{"lights.direct", "sample"}, {"lights.direct_samples", "2"}},
                       "lights.direct_samples must be 1");
    expect_usage_error({{"bdlightcuts.emission", "nee"}},
                       "bdlightcuts.emission must be mis or hit");
    expect_usage_error({{"bdlightcuts.emission_samples", "0"}},
                       "bdlightcuts.emission_samples must be at least 1");
    expect_usage_error({{"bdlightcuts.rest_paths", "0"}},
                       "bdlightcuts.rest_paths must be at least 1");
    expect_usage_error({{"bdlightcuts.rest", "trace"}}, "bdlightcuts.rest must be path or drop");
    expect_usage_error({{"tree.reps", "0"}}, "tree.reps must be 1 to 256");
    expect_usage_error({{"tree.reps", "257"}}, "tree.reps must be 1 to 256");
    expect_usage_error({{"bdlightcuts.vsp_tree", "kd"}},
                       "bdlightcuts.vsp_tree must be depth or position");
}
