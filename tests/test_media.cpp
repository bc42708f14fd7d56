// Participating media: the Henyey-Greenstein phase function's sampling against its density,
// `path` through media against closed forms (Beer's law through an absorbing medium seen
// directly and through a slab bounded by interface surfaces, for the camera's rays and for
// the shadow rays; a scattering-only medium in a white furnace is 1 whatever its colour, phase
// function and density; by `path` and `bdpt`), light tracing and BDPT against path through a
// coloured cloud, and the refusals of what is not supported yet.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "chi2.h"
#include "core/rng.h"
#include "core/scratch.h"
#include "integrators/render_job.h"
#include "materials/beam_diffusion.h"
#include "media/medium.h"
#include "media_test_helpers.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"
#include "sampling/warps.h"
#include "scene/scene_desc.h"
#include "transport/phase_bxdf.h"

using namespace ml;
using namespace ml::test;

TEST(MediaChi2, HenyeyGreensteinSamplesMatchItsDensity) {
    const float gs[] = {-0.7f, 0.f, 0.3f, 0.9f};
    const double alpha = chi2::sidak_alpha(0.01, 4);
    const Vec3 wo = normalize(Vec3(0.3f, -0.5f, 0.8f));
    for (float g : gs) {
        chi2::Options opt;
        opt.seed = uint64_t(7 + 100 * g);
        auto r = chi2::test(
            [&](Rng& rng) -> std::optional<Vec3> {
                return sample_hg_phase(wo, g, Vec2(rng.next_float(), rng.next_float()));
            },
            [&](const Vec3& w) { return double(hg_phase(wo, w, g)); }, opt);
        EXPECT_GT(r.p_value, alpha) << "g " << g << ": " << r.message;
    }
    // pbrt-v4's convention: g > 0 scatters forward, away from wo.
    EXPECT_GT(hg_phase(wo, -wo, 0.5f), hg_phase(wo, wo, 0.5f));
}

TEST(MediaPhase, ThePhaseBxdfIsThePhaseFunctionEitherWayAndBoundsItOverCones) {
    // The many-light integrators' stand-in for a BSDF at a point in a medium: f |cos| is the
    // phase function at a gather point (f(arrival, wi) |cos wi|) and at a VPL
    // (f(w, arrival) |cos w|); its density is the phase function's; and max_value_bound is never
    // below f |cos| over any cone of directions (Lightcuts' bound).
    Rng rng(17);
    auto dir = [&] { return sample_uniform_sphere({rng.next_float(), rng.next_float()}); };
    for (float g : {-0.8f, -0.2f, 0.f, 0.5f, 0.95f}) {
        SCOPED_TRACE(g);
        ScratchBuffer scratch;
        const Vec3 arrival = dir();
        const Bsdf phase = phase_bsdf(arrival, g, scratch);
        const Vec3 n = phase.frame().n;
        for (int i = 0; i < 200; ++i) {
            const Vec3 w = dir();
            const float p = hg_phase(arrival, w, g);
            EXPECT_NEAR(phase.eval(arrival, w).g * abs_dot(w, n), p, 1e-4f * p + 1e-7f);
            EXPECT_NEAR(phase.eval(w, arrival).g * abs_dot(w, n), p, 1e-4f * p + 1e-7f);
            EXPECT_NEAR(phase.pdf_solid_angle(arrival, w), p, 1e-4f * p + 1e-7f);
        }
        EXPECT_NEAR(phase.max_value_bound(arrival, DirectionCone::entire_sphere()).g,
                    hg_phase(arrival, -arrival, g) > hg_phase(arrival, arrival, g)
                        ? hg_phase(arrival, -arrival, g)
                        : hg_phase(arrival, arrival, g),
                    1e-3f);
        for (int c = 0; c < 100; ++c) {
            const DirectionCone cone(dir(), 2 * rng.next_float() - 1);
            const float bound = phase.max_value_bound(arrival, cone).g;
            const Frame f = Frame::from_z(cone.axis);
            for (int i = 0; i < 50; ++i) {
                // A direction in the cone: cos theta uniform in [cos_theta, 1].
                const float ct = cone.cos_theta + (1 - cone.cos_theta) * rng.next_float();
                const float st = std::sqrt(std::max(0.f, 1 - ct * ct)),
                            phi = 2 * kPi * rng.next_float();
                const Vec3 w = f.to_world(Vec3(st * std::cos(phi), st * std::sin(phi), ct));
                EXPECT_LE(phase.eval(arrival, w).g * abs_dot(w, n), bound * 1.0001f + 1e-7f);
            }
        }
    }
}

TEST(Media, AnAbsorbingMediumTransmitsAsBeersLaw) {
    // An orthographic view of an emitter 2 units away through a medium of sigma_a (0.5, 1, 2):
    // every pixel sees exp(-2 sigma_a).
    for (const char* type : {"homogeneous", "uniformgrid"}) {
        SCOPED_TRACE(type);
        const std::string scene =
            medium(type, "\"rgb sigma_a\" [ 0.5 1 2 ] \"rgb sigma_s\" [ 0 0 0 ]") +
            "MediumInterface \"\" \"m\"\n"
            "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"orthographic\"\n"
            "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
            "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 5 ]\n"
            "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
            "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
            "  \"point3 P\" [ -5 -5 2  -5 5 2  5 5 2  5 -5 2 ]\n";
        const Image img = render_text(scene, options(256)).image;
        const double sigma[3] = {0.5, 1, 2};
        for (int c = 0; c < 3; ++c) expect_channel(img, c, std::exp(-2 * sigma[c]), 0.05);
    }
}

TEST(Media, ASlabBetweenInterfacesDimsTheLightBothWays) {
    // A diffuse floor of albedo 0.5 lit from straight above, seen from straight above, under a
    // slab 0.5 thick of an absorbing medium bounded by an interface box: the camera's ray and
    // the shadow ray each cross it once, so the floor shows 0.5 exp(-2 * 0.5 sigma_a). The
    // shadow rays pass the interfaces (transmittance in closed form, or by ratio tracking in
    // the grid).
    for (const char* type : {"homogeneous", "uniformgrid"}) {
        SCOPED_TRACE(type);
        const std::string world =
            medium(type, "\"rgb sigma_a\" [ 0.4 1 1.6 ] \"rgb sigma_s\" [ 0 0 0 ]") +
            "AttributeBegin\nMediumInterface \"m\" \"\"\nMaterial \"interface\"\n" +
            box(Vec3(-8, -8, 1), Vec3(8, 8, 1.5f)) +
            "AttributeEnd\nMaterial \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
            "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
            "  \"point3 P\" [ -6 -6 0  6 -6 0  6 6 0  -6 6 0 ]\n";
        const std::string scene = lit_from_above(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\"", 16, 16, 64, world);
        const Image img = render_text(scene, options(64)).image;
        const double sigma[3] = {0.4, 1, 1.6};
        for (int c = 0; c < 3; ++c) expect_channel(img, c, 0.5 * std::exp(-sigma[c]), 0.05);
    }
}

TEST(Media, AScatteringMediumInAWhiteFurnaceIsOne) {
    // Inside a sphere that emits 1 and reflects nothing, a medium that only scatters (coloured,
    // forward-scattering) leaves every ray's radiance 1: each path ends on the wall.
    for (const char* type : {"homogeneous", "uniformgrid"}) {
        SCOPED_TRACE(type);
        const std::string scene =
            medium(type,
                   "\"rgb sigma_a\" [ 0 0 0 ] \"rgb sigma_s\" [ 0.3 0.8 1.5 ] "
                   "\"float g\" [ 0.6 ]") +
            "MediumInterface \"m\" \"m\"\n"
            "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" [ 60 ]\n"
            "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
            "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 1000 ]\n"
            "WorldBegin\nAttributeBegin\nReverseOrientation\n"
            "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
            "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
            "Shape \"sphere\" \"float radius\" [ 3 ]\nAttributeEnd\n";
        const Image img = render_text(scene, options(64)).image;
        for (int c = 0; c < 3; ++c) expect_channel(img, c, 1.0, 0.03);
        // BDPT: medium vertices on both subpaths, joined through the medium's transmittance.
        RenderOptions bd = options(64);
        bd.integrator = "bdpt";
        const Image bidir = render_text(scene, bd).image;
        for (int c = 0; c < 3; ++c) expect_channel(bidir, c, 1.0, 0.03);
    }
}

// A box of coloured, forward-scattering medium of `type` bounded by interfaces, over a grey
// floor under an area light, seen from outside, 24x18, max depth 4.
TEST(Media, LightTracingAndBdptAgreeWithPathThroughAColouredCloud) {
    // The coloured cloud seen from outside (a camera inside a scattering medium gives light
    // tracing unbounded variance: vertices next to the lens). Light paths scatter in the cloud
    // (spectral tracking) and reach the lens through it; per channel against path, pixel by
    // pixel.
    for (const char* type : {"homogeneous", "uniformgrid"}) {
        SCOPED_TRACE(type);
        expect_integrators_agree_with_path(coloured_cloud(type),
                                           {{"lighttracer", 2048}, {"bdpt", 512}});
    }
}

TEST(Media, ManyLightIntegratorsAgreeWithPathThroughAColouredCloud) {
    // VPLs left where light paths scatter in the cloud, re-emitting through the phase function,
    // and gather points where camera rays scatter in it, every connection through the medium's
    // transmittance. Each VPL set's draw moves the whole image (by about 2% in blue over 16 sets
    // of 2000 VPLs), so the image means are compared, per channel, over many sets.
    for (const char* type : {"homogeneous", "uniformgrid"}) {
        SCOPED_TRACE(type);
        const std::string scene = coloured_cloud(type);
        const Image path = render_text(scene, options(2048)).image;
        // Gather points on camera rays: four stratified by transmittance on each stretch through
        // the homogeneous cloud (the default), or one where delta tracking finds the ray scatter
        // (gather.medium_points=0, and always in the grid).
        for (auto [integrator, spp, points] :
             {std::tuple{"lightcuts", 64, "4"}, std::tuple{"mdlightcuts", 256, "4"},
              std::tuple{"mdlightcuts", 512, "0"}, std::tuple{"stochasticlightcuts", 512, "4"}}) {
            if (std::string(type) != "homogeneous" &&
                (std::string(integrator) == "lightcuts" || std::string(points) == "0"))
                continue;  // the slowest, and the same as the default: the homogeneous cloud
            SCOPED_TRACE(std::string(integrator) + ", gather.medium_points=" + points);
            RenderOptions opt = options(spp);
            opt.integrator = integrator;
            opt.set["vpl.count"] = "2000";
            opt.set["gather.medium_points"] = points;
            const Image other = render_text(scene, opt).image;
            for (int c = 0; c < 3; ++c) {
                const double a = channel_stats(other, c).mean, b = channel_stats(path, c).mean;
                EXPECT_NEAR(a / b, 1.0, 0.03)
                    << "channel " << c << ": " << integrator << " " << a << ", path " << b;
            }
        }
    }
}

TEST(Media, BidirectionalLightcutsAgreesWithPathThroughAColouredCloud) {
    // Eye paths that scatter in the cloud (delta tracking, spectral tracking) leave VSPs there,
    // shaded through the phase function; each split's weight takes the phase function for the
    // lobes at medium vertices; the remainder is path traced through the media. Per channel
    // against path, with the default weights and with a clamp so small that almost every
    // VSP-VPL join hands its path to longer eye paths and the remainder (c_clamp 1e-6).
    for (const char* type : {"homogeneous", "uniformgrid"}) {
        SCOPED_TRACE(type);
        const std::string scene = coloured_cloud(type);
        const Image path = render_text(scene, options(2048)).image;
        for (const char* c_clamp : {"0.01", "0.000001"}) {
            SCOPED_TRACE(std::string("c_clamp ") + c_clamp);
            RenderOptions opt = options(128);
            opt.integrator = "bdlightcuts";
            opt.set["vpl.count"] = "2000";
            opt.set["bdlightcuts.c_clamp"] = c_clamp;
            const Image other = render_text(scene, opt).image;
            expect_agrees_with_path(other, path, "bdlightcuts", 0.02);
        }
    }
}

TEST(Media, ManyLightRendersInACloudAreTheSameAtAnyThreadCount) {
    // VPL paths, gather points, eye paths and ratio tracking through the grid all draw from
    // per-path and per-pixel samplers: a seed gives one image whatever the threads.
    for (const char* integrator :
         {"lightcuts", "mdlightcuts", "stochasticlightcuts", "bdlightcuts"}) {
        SCOPED_TRACE(integrator);
        RenderOptions opt = options(2);
        opt.integrator = integrator;
        opt.set["vpl.count"] = "500";
        opt.threads = 1;
        const Image one = render_text(coloured_cloud("uniformgrid"), opt).image;
        opt.threads = 2;
        const Image two = render_text(coloured_cloud("uniformgrid"), opt).image;
        ASSERT_EQ(one.pixels.size(), two.pixels.size());
        for (size_t i = 0; i < one.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) ASSERT_EQ(one.pixels[i][c], two.pixels[i][c]) << i;
    }
}

TEST(Media, BidirectionalLightcutsAgreesWithPathInFogUnderASpot) {
    // pbrt-v4's media_fog: VSPs on camera rays through the fog joined to the spot light, weighed
    // by MIS against a point drawn equiangularly towards it on each stretch (max depth 1), and
    // with VPLs in the fog and the remainder path traced (max depth 3). Per channel against
    // `path`, whose equiangular sampling and tracking are its own code. (Against pbrt-v4's image
    // the means agree within 0.5%, but one dim corner block, 1.7% of the image's mean, is 6%
    // above it by `path` too.)
    const std::string file = MANYLIGHT_SOURCE_DIR "/tests/scenes/media_fog.pbrt";
    for (int depth : {1, 3}) {
        SCOPED_TRACE("max depth " + std::to_string(depth));
        RenderOptions opt = options(depth == 1 ? 1024 : 256);
        opt.max_depth = depth;
        const Image path = render_scene(parse_scene_file(file), opt).image;
        opt.integrator = "bdlightcuts";
        opt.spp = depth == 1 ? 256 : 64;
        const Image other = render_scene(parse_scene_file(file), opt).image;
        expect_agrees_with_path(other, path, "bdlightcuts", 0.02);
    }
}

TEST(Media, BidirectionalLightcutsInFogUnderASpotIsTheSameAtAnyThreadCount) {
    // The equiangular samples towards the spot light draw from the pixel's sampler too.
    RenderOptions opt = options(4);
    opt.integrator = "bdlightcuts";
    opt.threads = 1;
    const std::string file = MANYLIGHT_SOURCE_DIR "/tests/scenes/media_fog.pbrt";
    const Image one = render_scene(parse_scene_file(file), opt).image;
    opt.threads = 2;
    const Image two = render_scene(parse_scene_file(file), opt).image;
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    for (size_t i = 0; i < one.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(one.pixels[i][c], two.pixels[i][c]) << i;
}

TEST(Media, LightcutsInACloudStayWithinTheirBoundsOfTheVplSum) {
    // Lightcuts against the brute-force sum over the same VPLs (`vpl`, same seed): the cuts'
    // bounds on the phase function (gather points and VPLs in the medium) hold node by node
    // (`lightcuts.verify`), and the images agree.
    const std::string scene = coloured_cloud("homogeneous");
    RenderOptions opt = options(8);
    opt.set["vpl.count"] = "2000";
    opt.set["gather.medium_points"] = "2";
    opt.set["lights.direct"] = "points";  // the area light's points are cut too
    opt.integrator = "vpl";
    const Image exact = render_text(scene, opt).image;
    opt.integrator = "lightcuts";
    opt.set["lightcuts.verify"] = "true";
    const RenderOutput cut = render_text(scene, opt);
    const nlohmann::json& json = cut.figures.integrator_stats.at("lightcuts");
    EXPECT_GT(json.at("verify").at("nodes").get<double>(), 1000);
    EXPECT_EQ(json.at("verify").at("violations").get<double>(), 0) << json.dump();
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(channel_stats(cut.image, c).mean / channel_stats(exact, c).mean, 1.0, 0.01)
            << "channel " << c;
}

TEST(MediaErrors, WhatIsNotSupportedSaysSo) {
    const std::string fog =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMediumInterface \"\" \"fog\"\n"
        "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\"\n"
        "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
        "WorldBegin\nLightSource \"point\" \"point3 from\" [ 0 0 1 ]\n";
    for (const char* integrator : {"cmlt", "whitted", "direct"}) {
        RenderOptions opt = options(1);
        opt.integrator = integrator;
        try {
            render_text(fog, opt);
            ADD_FAILURE() << integrator << " rendered a scene with media";
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find("does not render participating media"),
                      std::string::npos)
                << e.what();
        }
    }
    // Light paths start at the lights, never in an emitting medium: what joins light paths to
    // the lens refuses it, and so does Veach's MLT, whose paths end on lights.
    for (const char* integrator : {"lighttracer", "mlt"}) try {
            RenderOptions opt = options(1);
            opt.integrator = integrator;
            render_text(
                "MakeNamedMedium \"glow\" \"string type\" \"homogeneous\" \"rgb Le\" [ 1 1 1 ]\n"
                "MediumInterface \"\" \"glow\"\nLookAt 0 0 0  0 0 1  0 1 0\nCamera "
                "\"perspective\"\n"
                "Film \"rgb\" \"integer xresolution\" [ 4 ] \"integer yresolution\" [ 4 ]\n"
                "WorldBegin\nLightSource \"point\" \"point3 from\" [ 0 0 1 ]\n",
                opt);
            ADD_FAILURE() << integrator << " rendered an emitting medium";
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find("does not carry light emitted by a medium"),
                      std::string::npos)
                << e.what();
        }
    // What the many-light integrators cannot do in media yet says so.
    for (auto [setting, value, message] :
         {std::tuple{"vpl.sampler", "power", "vpl.sampler=power does not handle participating"},
          std::tuple{"lightcuts.reconstruct", "4", "lightcuts.reconstruct does not handle"}}) {
        RenderOptions opt = options(1);
        opt.integrator = "lightcuts";
        opt.set[setting] = value;
        try {
            render_text(fog, opt);
            ADD_FAILURE() << setting << "=" << value << " rendered a scene with media";
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    }
    try {
        RenderOptions opt = options(1);
        opt.integrator = "bdlightcuts";
        opt.set["bdlightcuts.guiding"] = "on";
        render_text(fog, opt);
        ADD_FAILURE() << "bdlightcuts.guiding=on rendered a scene with media";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("not guided in participating media"),
                  std::string::npos)
            << e.what();
    }
    expect_scene_error("WorldBegin\nMediumInterface \"smoke\" \"\"\nShape \"sphere\"\n", 3, 1,
                       "medium \"smoke\" is not defined");
    expect_scene_error(
        "MakeNamedMedium \"a\" \"string type\" \"uniformgrid\" \"float density\" [ 1 2 3 ]\n"
        "  \"integer nx\" [ 2 ]\n",
        1, 1, "3 \"density\" values where nx * ny * nz = 2 x 1 x 1");
    expect_scene_error("MakeNamedMedium \"a\" \"string type\" \"homogeneous\" \"float g\" [ 1 ]\n",
                       1, 1, "\"g\" must be in (-1, 1)");
    expect_scene_error("MakeNamedMedium \"a\" \"string type\" \"fluffy\"\n", 1, 1,
                       "unknown medium type \"fluffy\"");
    expect_scene_error(
        "MakeNamedMedium \"a\" \"string type\" \"rgbgrid\" \"rgb sigma_a\" [ 1 2 3  4 5 6 ]\n"
        "  \"rgb sigma_s\" [ 1 2 3 ]\n",
        1, 1, "2 \"sigma_a\" values but 1 \"sigma_s\" values");
    expect_scene_error(
        "MakeNamedMedium \"a\" \"string type\" \"rgbgrid\" \"rgb sigma_a\" [ 1 2 3  4 5 ]\n", 1, 45,
        "5 values, not a positive multiple of 3");
    expect_scene_error("MakeNamedMedium \"a\" \"string type\" \"rgbgrid\" \"rgb Le\" [ 1 2 3 ]\n",
                       1, 1, "needs \"rgb sigma_a\" or \"rgb sigma_s\" values");
}

TEST(Media, AnRgbGridIsTheUniformGridItSpellsOut) {
    // pbrt-v4's rgbgrid with each cell's coefficients and emission written out renders as the
    // uniformgrid of densities and emission scales they come from.
    const float d[8] = {0.2f, 1, 0.5f, 0.1f, 0.8f, 0.3f, 1.2f, 0.6f};
    const RGB sa(0.5f, 1, 2), ss(0.4f, 0.2f, 0.6f), Le(1, 2, 3);
    std::string dens, rgb_a, rgb_s, rgb_le, lescale;
    for (float v : d) {
        dens += fmt::format(" {}", v);
        lescale += fmt::format(" {}", 2 * v);
        rgb_a += fmt::format("  {} {} {}", sa.r * v, sa.g * v, sa.b * v);
        rgb_s += fmt::format("  {} {} {}", ss.r * v, ss.g * v, ss.b * v);
        rgb_le += fmt::format("  {} {} {}", Le.r * 2 * v, Le.g * 2 * v, Le.b * 2 * v);
    }
    const std::string box =
        " \"integer nx\" [ 2 ] \"integer ny\" [ 2 ] \"integer nz\" [ 2 ]"
        " \"point3 p0\" [ -2 -2 1 ] \"point3 p1\" [ 2 2 5 ] \"float g\" [ 0.3 ]\n";
    const std::string grid =
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [" + dens +
        " ] \"rgb sigma_a\" [ 0.5 1 2 ] \"rgb sigma_s\" [ 0.4 0.2 0.6 ] \"rgb Le\" [ 1 2 3 ]"
        " \"float Lescale\" [" +
        lescale + " ]" + box;
    const std::string rgb = "MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_a\" [" +
                            rgb_a + " ] \"rgb sigma_s\" [" + rgb_s + " ] \"rgb Le\" [" + rgb_le +
                            " ]" + box;
    auto render = [&](const std::string& medium_text) {
        return render_text(medium_text +
                               "MediumInterface \"\" \"m\"\nLookAt 0 0 0  0 0 1  0 1 0\n"
                               "Camera \"perspective\" \"float fov\" [ 50 ]\n"
                               "Film \"rgb\" \"integer xresolution\" [ 16 ] "
                               "\"integer yresolution\" [ 16 ]\nSampler \"independent\"\n"
                               "Integrator \"path\" \"integer maxdepth\" [ 3 ]\nWorldBegin\n"
                               "LightSource \"point\" \"point3 from\" [ 0.5 0.5 2 ] "
                               "\"rgb I\" [ 2 2 2 ]\n",
                           options(64))
            .image;
    };
    const Image a = render(grid), b = render(rgb);
    for (int c = 0; c < 3; ++c) {
        const MeanDifference m = mean_difference(b, a, c);
        EXPECT_NEAR(m.mean, 0, 0.005 * m.reference_mean) << "channel " << c;
    }
}

namespace {

// A point light I at (0, 1.3, 2) in a homogeneous medium, seen by an orthographic camera from
// z = 0 along +z over the screen [-1, 1]^2, with a black wall at z = 4: single scattering
// (max depth 1). Its image mean by quadrature: over the screen, along each ray, the light
// scattered at distance t by sigma_s and the phase function, dimmed along both legs.
double single_scattering_mean(double sigma_t, double sigma_s, double g, double I) {
    const int n = 48, m = 400;
    const Vec3 light(0, 1.3f, 2);
    double sum = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double x = -1 + (i + 0.5) * 2.0 / n, y = -1 + (j + 0.5) * 2.0 / n;
            double line = 0;
            for (int k = 0; k <= m; ++k) {  // Simpson's rule over t in [0, 4]
                const double t = 4.0 * k / m;
                const Vec3 d = light - Vec3(float(x), float(y), float(t));
                const double r = length(d);
                const float phase = hg_phase(Vec3(0, 0, -1), d / float(r), float(g));
                const double f = std::exp(-sigma_t * (t + r)) * sigma_s * phase * I / (r * r);
                line += f * (k == 0 || k == m ? 1 : (k % 2 ? 4 : 2));
            }
            sum += line * (4.0 / m) / 3;
        }
    return sum / (n * n);
}

std::string point_light_in_medium(const char* equiangular) {
    return std::string(
               "MakeNamedMedium \"m\" \"string type\" \"homogeneous\"\n"
               "  \"rgb sigma_a\" [ 0.3 0.2 0.1 ] \"rgb sigma_s\" [ 0.2 0.3 0.4 ] \"float g\" "
               "[ 0.5 ]\n"
               "MediumInterface \"\" \"m\"\nLookAt 0 0 0  0 0 1  0 1 0\nCamera \"orthographic\"\n"
               "Film \"rgb\" \"integer xresolution\" [ 24 ] \"integer yresolution\" [ 24 ]\n"
               "PixelFilter \"box\"\nSampler \"independent\"\n"
               "Integrator \"path\" \"integer maxdepth\" [ 1 ] \"bool equiangular\" ") +
           equiangular +
           "\nWorldBegin\nLightSource \"point\" \"point3 from\" [ 0 1.3 2 ] \"rgb I\" [ 2 2 2 ]\n"
           "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
           "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
           "  \"point3 P\" [ -9 -9 4  -9 9 4  9 9 4  9 -9 4 ]\n";
}

}  // namespace

TEST(Media, SingleScatteringFromAPointLightMatchesQuadrature) {
    // With and without equiangular sampling (MIS with delta tracking), each channel against
    // the quadrature; equiangular sampling must also cut the noise: the per-pixel spread
    // between two renders of different seeds.
    const double sigma_s[3] = {0.2, 0.3, 0.4};
    double noise[2][3];
    for (int on = 0; on < 2; ++on) {
        SCOPED_TRACE(on ? "equiangular" : "delta tracking alone");
        const std::string scene = point_light_in_medium(on ? "true" : "false");
        const Image img = render_text(scene, options(64)).image;
        RenderOptions other = options(64);
        other.seed = 11;
        const Image again = render_text(scene, other).image;
        for (int c = 0; c < 3; ++c) {
            const double expected = single_scattering_mean(0.5, sigma_s[c], 0.5, 2);
            expect_channel(img, c, expected, 0.05);
            double d2 = 0;
            for (size_t i = 0; i < img.pixels.size(); ++i) {
                const double d = double(img.pixels[i][c]) - again.pixels[i][c];
                d2 += d * d;
            }
            noise[on][c] = std::sqrt(d2 / (2.0 * double(img.pixels.size())));
        }
    }
    for (int c = 0; c < 3; ++c) EXPECT_LT(noise[1][c], 0.7 * noise[0][c]) << "channel " << c;
}

TEST(Media, APresetIsPbrtV4sMeasuredCoefficientsTimesScale) {
    // Jensen et al. 2001, table 2 (mm^-1): Skin1 sigma_s' = 0.74 / 0.88 / 1.01, sigma_a = 0.032 /
    // 0.17 / 0.48; Narasimhan et al. 2006: Regular Milk sigma_s' 4.5513 / 5.8294 / 7.136.
    const SceneDesc skin = parse_scene_string(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" [ \"Skin1\" ]\n"
        "  \"float scale\" [ 2 ]\nWorldBegin\n",
        ".", "test.pbrt");
    ASSERT_EQ(skin.media.size(), 1u);
    const MediumProperties p = skin.media[0]->at(Vec3(0.3f, -2, 5));
    const float sa[3] = {0.032f, 0.17f, 0.48f}, ss[3] = {0.74f, 0.88f, 1.01f};
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(p.sigma_a[c], 2 * sa[c]) << c;
        EXPECT_FLOAT_EQ(p.sigma_s[c], 2 * ss[c]) << c;
    }
    const SceneDesc milk = parse_scene_string(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" "
        "[ \"Regular Milk\" ]\nWorldBegin\n",
        ".", "test.pbrt");
    EXPECT_FLOAT_EQ(milk.media[0]->at(Vec3(0, 0, 0)).sigma_s.b, 7.136f);
    expect_scene_error(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" [ \"Skin3\" ]\n",
        1, 49, "unknown \"preset\" \"Skin3\" (pbrt-v4's are \"Apple\", ");
    expect_scene_error(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" [ \"Skin1\" ]\n"
        "  \"rgb sigma_s\" [ 1 1 1 ]\n",
        1, 49, "leave out \"sigma_a\" and \"sigma_s\"");
    // pbrt-v4 reads a preset for homogeneous media only.
    expect_scene_error(
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ]\n"
        "  \"string preset\" [ \"Skin1\" ]\n",
        2, 3, "\"string preset\" is unknown or unused here");
}

TEST(Media, ACloudFillsItsFootAndThinsToNothingAtHeightOne) {
    // pbrt-v4's cloud density, in medium space: 1 wherever y <= 0 (the 2 (0.5 - y) floor), 0 at
    // y = 1 (the (1 - y) falloff), noise between; zero outside its box [p0, p1], and a majorant
    // of sigma_a + sigma_s there.
    const SceneDesc desc = parse_scene_string(
        "Translate 10 0 0\nMakeNamedMedium \"c\" \"string type\" \"cloud\" \"rgb sigma_a\" "
        "[ 0.5 1 2 ]\n  \"rgb sigma_s\" [ 3 2 1 ] \"point3 p0\" [ 0 -1 0 ] \"point3 p1\" "
        "[ 1 1 1 ]\nWorldBegin\n",
        ".", "test.pbrt");
    const Medium& m = *desc.media[0];
    EXPECT_EQ(m.type(), "cloud");
    Rng rng(5);
    int between = 0;
    for (int i = 0; i < 400; ++i) {
        const float x = rng.next_float(), z = rng.next_float();
        const MediumProperties foot = m.at(Vec3(10 + x, -rng.next_float(), z));
        EXPECT_FLOAT_EQ(foot.sigma_a.g, 1);
        EXPECT_FLOAT_EQ(foot.sigma_s.r, 3);
        EXPECT_NEAR(m.at(Vec3(10 + x, 0.99999f, z)).sigma_s.r, 0, 1e-3f);
        const float mid = m.at(Vec3(10 + x, 0.5f + 0.4f * rng.next_float(), z)).sigma_s.r / 3;
        EXPECT_GE(mid, 0);
        EXPECT_LE(mid, 1);
        between += mid > 0.01f && mid < 0.99f;
    }
    EXPECT_GT(between, 40);  // the noise, not a constant
    const auto seg = m.majorant(Ray{Vec3(0, 0.5f, 0.5f), Vec3(1, 0, 0)}, 100);
    ASSERT_TRUE(seg.has_value());
    EXPECT_NEAR(seg->t0, 10, 1e-4f);
    EXPECT_NEAR(seg->t1, 11, 1e-4f);
    EXPECT_FLOAT_EQ(seg->sigma_maj, 3.5f);  // the largest channel of sigma_a + sigma_s
    EXPECT_FALSE(m.majorant(Ray{Vec3(0, 0.5f, 0.5f), Vec3(-1, 0, 0)}, 100).has_value());
    expect_scene_error("MakeNamedMedium \"c\" \"string type\" \"cloud\" \"float density\" [ -1 ]\n",
                       1, 1, "\"density\" and \"wispiness\" must be finite and >= 0");
}

TEST(Subsurface, ASlabTransmitsThroughItsFresnelBoundaryAsBeersLaw) {
    // An orthographic view, at normal incidence, of an emitter of 1 behind a slab 2 thick of an
    // absorbing subsurface material (eta 1.5: R = 0.04 at each face; sigma_a (1, 2, 4) times
    // "scale" 0.5): (1 - R)^2 T / (1 - R^2 T^2), T = exp(-2 sigma_a), the boundary's internal
    // reflections summed (the emitter reflects nothing).
    const std::string scene =
        "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"orthographic\"\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 16 ]\n"
        "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 12 ]\n"
        "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -5 -5 4  -5 5 4  5 5 4  5 -5 4 ]\nAttributeEnd\n"
        "Material \"subsurface\" \"float eta\" [ 1.5 ] \"rgb sigma_a\" [ 1 2 4 ]\n"
        "  \"rgb sigma_s\" [ 0 0 0 ] \"float scale\" [ 0.5 ]\n" +
        box(Vec3(-8, -8, 1), Vec3(8, 8, 3));
    const Image img = render_text(scene, options(1024)).image;
    const double R = 0.04, sigma[3] = {0.5, 1, 2};
    for (int c = 0; c < 3; ++c) {
        const double T = std::exp(-2 * sigma[c]);
        expect_channel(img, c, (1 - R) * (1 - R) * T / (1 - R * R * T * T), 0.02);
    }
}

TEST(Subsurface, IsItsDielectricBoundaryOverItsMeasuredMedium) {
    // A subsurface sphere of Ketchup (pbrt-v4's measured coefficients, mm^-1, as unit^-1)
    // renders pixel for pixel as a dielectric sphere of the same eta and roughness with a
    // homogeneous medium of those coefficients inside (MediumInterface), by `path` and by a
    // many-light integrator.
    auto scene = [](const std::string& material) {
        return "LookAt 0 2 -6  0 0.8 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
               "Film \"rgb\" \"integer xresolution\" [ 20 ] \"integer yresolution\" [ 16 ]\n"
               "Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 8 ]\n"
               "WorldBegin\n"
               "MakeNamedMedium \"k\" \"string type\" \"homogeneous\" \"rgb sigma_a\" "
               "[ 0.061 0.97 1.45 ] \"rgb sigma_s\" [ 0.18 0.07 0.03 ]\n"
               "AttributeBegin\nTranslate 0 4 0\nAreaLightSource \"diffuse\" \"rgb L\" "
               "[ 20 20 20 ]\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
               "  \"point3 P\" [ -1 0 -1  1 0 -1  1 0 1  -1 0 1 ]\nAttributeEnd\n"
               "Material \"diffuse\"\nShape \"trianglemesh\" \"integer indices\" "
               "[ 0 1 2 0 2 3 ]\n  \"point3 P\" [ -5 0 -5  -5 0 5  5 0 5  5 0 -5 ]\n"
               "AttributeBegin\n" +
               material + "Translate 0 0.8 0\nShape \"sphere\" \"float radius\" [ 0.8 ]\n" +
               "AttributeEnd\n";
    };
    const std::string subsurface = scene(
        "Material \"subsurface\" \"string name\" [ \"Ketchup\" ]\n"
        "  \"float roughness\" [ 0.2 ]\n");
    const std::string dielectric = scene(
        "MediumInterface \"k\" \"\"\nMaterial \"dielectric\" \"float eta\" [ 1.33 ]\n"
        "  \"float roughness\" [ 0.2 ]\n");
    for (const char* integrator : {"path", "mdlightcuts"}) {
        SCOPED_TRACE(integrator);
        RenderOptions opt = options(4);
        opt.integrator = integrator;
        const Image a = render_text(subsurface, opt).image, b = render_text(dielectric, opt).image;
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        double sum = 0;
        for (size_t i = 0; i < a.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(a.pixels[i][c], b.pixels[i][c], 1e-4f * (1 + b.pixels[i][c])) << i;
                sum += a.pixels[i][c];
            }
        EXPECT_GT(sum, 0);
    }
}

TEST(Subsurface, ReflectanceInvertsAsPbrtV4sDiffusionTable) {
    // "reflectance" gives each channel the single-scattering albedo whose diffuse reflectance by
    // photon beam diffusion is that reflectance. The albedos pbrt-v4 (5f7a606) finds, printed by
    // a program linked against its library (BSSRDFTable(100, 64), ComputeBeamDiffusionBSSRDF,
    // InvertCatmullRom), for g, eta and reflectance:
    struct Case {
        float g, eta, reflectance;
        double rho;
    };
    const Case cases[] = {{0, 1.33f, 0.05f, 0.4207084},    {0, 1.33f, 0.2f, 0.8182444},
                          {0, 1.33f, 0.5f, 0.9695290},     {0, 1.33f, 0.8f, 0.9965813},
                          {0, 1.5f, 0.05f, 0.4970460},     {0, 1.5f, 0.2f, 0.8725300},
                          {0, 1.5f, 0.5f, 0.9813302},      {0, 1.5f, 0.8f, 0.9980794},
                          {0.5f, 1.33f, 0.05f, 0.7027565}, {0.5f, 1.33f, 0.2f, 0.9270585},
                          {0.5f, 1.33f, 0.5f, 0.9887539},  {0.5f, 1.5f, 0.2f, 0.9482870},
                          {0.5f, 1.5f, 0.5f, 0.9926683}};
    for (const Case& c : cases) {
        const BeamDiffusionTable table(c.g, c.eta);
        const double rho = table.albedo_for(c.reflectance);
        // Near an albedo of 1 the reflectance moves with 1 - rho: compare that, within 2%.
        EXPECT_NEAR(1 - rho, 1 - c.rho, 0.02 * (1 - c.rho) + 1e-6)
            << "g " << c.g << ", eta " << c.eta << ", reflectance " << c.reflectance;
        EXPECT_NEAR(table.effective_albedo(float(rho)), c.reflectance, 1e-4);
    }
    // The coefficients: sigma_s = rho / mfp, sigma_a = (1 - rho) / mfp.
    const BeamDiffusionTable table(0, 1.33f);
    RGB sa, ss;
    subsurface_from_diffuse(table, RGB(0.05f, 0.2f, 0.5f), RGB(0.5f, 1, 2), &sa, &ss);
    EXPECT_NEAR(ss.r, 0.4207084 / 0.5, 0.02);
    EXPECT_NEAR(sa.g, 1 - 0.8182444, 0.004);
    EXPECT_NEAR(ss.b + sa.b, 0.5, 1e-6);
}

TEST(Subsurface, WhatItCannotTakeSaysSo) {
    const std::string head = "WorldBegin\nMaterial \"subsurface\" ";
    expect_scene_error(head + "\"rgb mfp\" [ 1 1 1 ]\n", 2, 23,
                       "\"mfp\" goes with \"reflectance\"");
    expect_scene_error(head + "\"rgb reflectance\" [ 0.5 0.5 0.5 ] \"rgb sigma_a\" [ 1 1 1 ]\n", 2,
                       23, "\"reflectance\" gives sigma_a and sigma_s");
    expect_scene_error(head + "\"rgb reflectance\" [ 0.5 0.5 0.5 ] \"rgb mfp\" [ 1 0 1 ]\n", 2, 57,
                       "the mean free path (\"mfp\" times \"scale\") must be positive");
    expect_scene_error(head + "\"string name\" [ \"Jam\" ]\n", 2, 23,
                       "unknown \"name\" \"Jam\" (pbrt-v4's are \"Apple\"");
    expect_scene_error(head + "\"string name\" [ \"Apple\" ] \"float g\" [ 0.5 ]\n", 2, 49,
                       "\"g\" with a measured medium's \"name\"");
    expect_scene_error(head + "\"rgb sigma_a\" [ 1 1 1 ]\n", 2, 23,
                       "\"sigma_a\" and \"sigma_s\" go together");
    expect_scene_error(
        "WorldBegin\nTexture \"t\" \"spectrum\" \"checkerboard\"\n"
        "Material \"subsurface\" \"texture sigma_a\" \"t\" \"rgb sigma_s\" [ 1 1 1 ]\n",
        3, 23, "a textured \"sigma_a\" is not supported");
    // Its medium fills the shape: a mix, one material or the other per hit, has no inside.
    expect_scene_error(
        "WorldBegin\nMakeNamedMaterial \"s\" \"string type\" \"subsurface\"\n"
        "MakeNamedMaterial \"d\" \"string type\" \"diffuse\"\n"
        "Material \"mix\" \"string materials\" [ \"s\" \"d\" ]\n",
        4, 16, "the \"subsurface\" material \"s\" cannot be mixed");
}

TEST(Media, TheBlackbodyTableFollowsPlanckFromAHundredKelvin) {
    // pbrt-v4's temperature emission, (T - offset) * scale kelvin: nothing at 100 K or below, and
    // the table's interpolation within 0.5% of the direct evaluation in between.
    const BlackbodyTable table(200, 1.5f, 0, 3000);
    EXPECT_TRUE(table.at(266).is_black());  // 99 K
    EXPECT_TRUE(table.at(-50).is_black());
    for (float raw : {300.f, 1234.5f, 2000.f, 2999.f}) {
        const RGB a = table.at(raw), b = blackbody_radiance_rgb((raw - 200) * 1.5f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.005f * b.max_component()) << raw;
    }
    // Hotter is brighter and bluer.
    const RGB warm = blackbody_radiance_rgb(2000), hot = blackbody_radiance_rgb(6000);
    EXPECT_GT(warm.r, 4 * warm.b);
    EXPECT_GT(hot.b / hot.r, warm.b / warm.r);
    EXPECT_TRUE(BlackbodyTable(0, 1, 0, 90).empty());
    // A temperature past float's range neither fills memory nor stops glowing past the table.
    const BlackbodyTable huge(0, 1, 0, 1e30f);
    const RGB far = huge.at(2e5f), direct = blackbody_radiance_rgb(2e5f);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(far[c], direct[c]);
    EXPECT_GT(far.b, 0);
}
