// The pbrt-v4 features of tests/scenes/, each rendered by manylight at the scene's own samples
// per pixel and compared with pbrt-v4's render of the same file at 1024 spp, committed beside it
// (tests/scenes/NAME.exr, made by tests/scenes/pbrt-v4-references.sh; a scene without one is
// skipped and says so): every channel's mean within 2% and every 16x16 block's within 10%. The
// scenes keep spectral rendering from hiding a difference: max depth 1 or 2, neutral colours
// where light bounces.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "film/image.h"
#include "film/image_metrics.h"
#include "integrators/render_job.h"
#include "scene/scene_desc.h"

using namespace ml;

namespace {

const std::string kScenes = MANYLIGHT_SOURCE_DIR "/tests/scenes/";

// `integrator`: ours instead of the scene's (the same image by another estimator); `spp`: instead
// of the scene's; `set`: settings (--set).
void expect_matches_pbrt(const std::string& name, const std::string& integrator = "", int spp = 0,
                         const std::map<std::string, std::string>& set = {}) {
    SCOPED_TRACE(name + (integrator.empty() ? "" : " by " + integrator));
    const std::string ref_path = kScenes + name + ".exr";
    // A scene whose reference has not been rendered yet is skipped, by name (the references
    // need a pbrt-v4 build, which CI does not have).
    if (!std::filesystem::exists(ref_path))
        GTEST_SKIP() << "no pbrt-v4 reference " << ref_path
                     << "; render it with tests/scenes/pbrt-v4-references.sh PBRT " << name;
    Image ref = read_image(ref_path);
    RenderOptions opt;
    opt.progress = false;
    opt.seed = 7;
    opt.integrator = integrator;
    if (spp > 0) opt.spp = spp;
    opt.set = set;
    Image img = render_scene(parse_scene_file(kScenes + name + ".pbrt"), opt).image;
    ASSERT_EQ(img.width, ref.width);
    ASSERT_EQ(img.height, ref.height);
    ImageDiff d = compare_images(img, ref);
    for (int c = 0; c < 3; ++c)
        EXPECT_LT(std::abs(d.mean_rel_diff[c]), 0.02)
            << "channel " << c << ": manylight " << d.mean_a[c] << ", pbrt-v4 " << d.mean_b[c];
    // Blocks whose pbrt-v4 mean is below 2% of the image's are left out: there 10% is noise.
    float floor = 0.02f * std::max({d.mean_b.r, d.mean_b.g, d.mean_b.b});
    std::vector<BlockDiff> worst = worst_blocks(img, ref, 16, 1, floor);
    if (!worst.empty()) {
        EXPECT_LT(worst[0].rel(), 0.10)
            << "block " << worst[0].x << "," << worst[0].y << " channel " << worst[0].channel
            << ": manylight " << worst[0].a << ", pbrt-v4 " << worst[0].ref;
    }
    std::printf("%s: mean rel diff %+.4f %+.4f %+.4f, worst block %.4f\n", name.c_str(),
                d.mean_rel_diff.r, d.mean_rel_diff.g, d.mean_rel_diff.b,
                worst.empty() ? 0.0 : worst[0].rel());
}

}  // namespace

TEST(PbrtReference, OrthographicCamera) { expect_matches_pbrt("camera_orthographic"); }
TEST(PbrtReference, OrthographicCameraWithLens) { expect_matches_pbrt("camera_orthographic_lens"); }
TEST(PbrtReference, SphericalCameraEquirectangular) { expect_matches_pbrt("camera_equirect"); }
TEST(PbrtReference, SphericalCameraEqualArea) { expect_matches_pbrt("camera_equalarea"); }
TEST(PbrtReference, BilerpTexture) { expect_matches_pbrt("tex_bilerp"); }
TEST(PbrtReference, DotsTexture) { expect_matches_pbrt("tex_dots"); }
TEST(PbrtReference, FbmTexture) { expect_matches_pbrt("tex_fbm"); }
TEST(PbrtReference, WrinkledTexture) { expect_matches_pbrt("tex_wrinkled"); }
TEST(PbrtReference, WindyTexture) { expect_matches_pbrt("tex_windy"); }
TEST(PbrtReference, MarbleTexture) { expect_matches_pbrt("tex_marble"); }
TEST(PbrtReference, MixTexture) { expect_matches_pbrt("tex_mix"); }
TEST(PbrtReference, DirectionMixTexture) { expect_matches_pbrt("tex_directionmix"); }
TEST(PbrtReference, ThinDielectricMaterial) { expect_matches_pbrt("mat_thindielectric"); }
TEST(PbrtReference, MixMaterial) { expect_matches_pbrt("mat_mix"); }
TEST(PbrtReference, CylinderShape) { expect_matches_pbrt("shape_cylinder"); }
TEST(PbrtReference, HomogeneousFogUnderASpotLight) { expect_matches_pbrt("media_fog"); }
TEST(PbrtReference, GridMediumBehindInterfaces) { expect_matches_pbrt("media_grid"); }
// Light paths through the same media: lighttracer's medium vertices and transmittance to the lens.
TEST(PbrtReference, HomogeneousFogByLightTracing) {
    expect_matches_pbrt("media_fog", "lighttracer");
}
TEST(PbrtReference, GridMediumByLightTracing) { expect_matches_pbrt("media_grid", "lighttracer"); }
TEST(PbrtReference, HomogeneousFogByBdpt) { expect_matches_pbrt("media_fog", "bdpt"); }
TEST(PbrtReference, GridMediumByPssmlt) {
    // PSSMLT's chains over BDPT's paths through the smoke: its image means (its 16x16 blocks
    // keep the chains' noise, above 10% at these samples) within 2% of pbrt-v4's.
    const std::string ref_path = kScenes + "media_grid.exr";
    if (!std::filesystem::exists(ref_path)) GTEST_SKIP() << "no pbrt-v4 reference " << ref_path;
    RenderOptions opt;
    opt.progress = false;
    opt.seed = 7;
    opt.spp = 256;
    opt.integrator = "pssmlt";
    const Image img = render_scene(parse_scene_file(kScenes + "media_grid.pbrt"), opt).image;
    const ImageDiff d = compare_images(img, read_image(ref_path));
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(d.mean_rel_diff[c]), 0.02) << "channel " << c;
}
TEST(PbrtReference, GridMediumByBdpt) { expect_matches_pbrt("media_grid", "bdpt"); }
// A spot light focused by a glass sphere into a beam in fog (Bitterli's volumetric-caustic): BDPT,
// the scene's integrator; no camera path reaches a spot light through glass.
TEST(PbrtReference, VolumetricCausticByBdpt) { expect_matches_pbrt("media_caustic"); }
// The many-light integrators in media: gather points where camera rays scatter, lit by the spot
// light through the fog (single scattering: max depth 1, no VPLs), and VPLs where light paths
// scatter in the smoke. The fog's blocks near the light converge slowly (points drawn by
// transmittance, not towards the light), hence its samples.
TEST(PbrtReference, HomogeneousFogByLightcuts) {
    expect_matches_pbrt("media_fog", "lightcuts", 256);
}
TEST(PbrtReference, GridMediumByMdlightcuts) { expect_matches_pbrt("media_grid", "mdlightcuts"); }
// bdlightcuts (so `manylight`) in media: VSPs where eye paths scatter in the smoke, joined to the
// VPLs there, its remainder path traced through the media. (In the fog under a spot light it is
// checked against `path`: tests/test_media.cpp.)
TEST(PbrtReference, GridMediumByBdlightcuts) { expect_matches_pbrt("media_grid", "bdlightcuts"); }
// igi (the viewer's preview) in media: unclamped and with VPLs enough that its one VPL set's
// draw does not hide a difference (256 VPLs: means from -3% to +6.5% over three seeds).
TEST(PbrtReference, GridMediumByIgi) {
    expect_matches_pbrt("media_grid", "igi", 0, {{"vpl.clamp", "0"}, {"igi.vpls", "4096"}});
}
TEST(PbrtReference, GridMediumByStochasticLightcuts) {
    expect_matches_pbrt("media_grid", "stochasticlightcuts");
}
// pbrt-v4's procedural cloud and a measured medium by "preset", by path and by VPLs in them.
TEST(PbrtReference, CloudAndPresetMedia) { expect_matches_pbrt("media_cloud"); }
TEST(PbrtReference, CloudAndPresetMediaByMdlightcuts) {
    expect_matches_pbrt("media_cloud", "mdlightcuts");
}
// A NanoVDB grid of smoke (ZIP-compressed), rotated and moved by the CTM at MakeNamedMedium.
TEST(PbrtReference, NanoVdbMedium) { expect_matches_pbrt("media_nanovdb"); }
// 1024 spp: the dim blocks at the top (3% of the image's mean) swing by 15% either way at 64,
// by 7% at 256 (each VPL set moves them).
TEST(PbrtReference, NanoVdbMediumByStochasticLightcuts) {
    expect_matches_pbrt("media_nanovdb", "stochasticlightcuts", 1024);
}
// Media glowing by temperature: a NanoVDB "temperature" grid and a uniformgrid's temperatures.
// 1024 spp: at the scene's 256 the blue of the fire's dim rim swings by 5% in a block, on top of
// the few percent by which pbrt-v4's spectral blackbody's colours part from ours there.
TEST(PbrtReference, MediaGlowingByTemperature) { expect_matches_pbrt("media_fire", "", 1024); }
// What the subsurface material renders: light walking through dense media inside rough
// dielectric spheres (pbrt-v4's own subsurface material is a BSSRDF, another model).
TEST(PbrtReference, DenseMediaInsideRoughDielectrics) { expect_matches_pbrt("media_walk"); }
// Tangent-space normals from an image on a diffuse floor and a rough conductor sphere, by path
// and through Lightcuts' bounds.
TEST(PbrtReference, NormalMap) { expect_matches_pbrt("mat_normalmap"); }
TEST(PbrtReference, NormalMapByLightcuts) { expect_matches_pbrt("mat_normalmap", "lightcuts"); }
TEST(PbrtReference, GoniometricLight) { expect_matches_pbrt("light_goniometric"); }
TEST(PbrtReference, ProjectionLight) { expect_matches_pbrt("light_projection"); }
TEST(PbrtReference, AreaLightImage) { expect_matches_pbrt("light_area_image"); }
TEST(PbrtReference, CoatedDiffuseMaterial) { expect_matches_pbrt("mat_coateddiffuse"); }
TEST(PbrtReference, CoatedConductorMaterial) { expect_matches_pbrt("mat_coatedconductor"); }
TEST(PbrtReference, CoatedConductorMaterialDepth2) {
    expect_matches_pbrt("mat_coatedconductor_depth2");
}
TEST(PbrtReference, InterfaceMaterial) { expect_matches_pbrt("mat_interface"); }
TEST(PbrtReference, CurveShape) { expect_matches_pbrt("shape_curve"); }
// Moving curves (an animated transform while the shutter is open): motion blur and its shadows.
TEST(PbrtReference, MovingCurves) { expect_matches_pbrt("shape_curve_motion"); }
// Cut-out curves: a checkerboard alpha and a constant 0.5, in camera and shadow rays.
TEST(PbrtReference, AlphaOnCurves) {
    expect_matches_pbrt("shape_curve_alpha");
    expect_matches_pbrt("shape_curve_alpha", "lightcuts");
}
TEST(PbrtReference, HairMaterial) { expect_matches_pbrt("mat_hair"); }
// A measured BRDF (a synthetic RGL .bsdf file, coloured spectra): by path, and by VPLs on it and
// gather points on it in `manylight`.
TEST(PbrtReference, MeasuredMaterial) { expect_matches_pbrt("mat_measured"); }
// An anisotropic file (phi_i over a whole turn) on two squares whose uv run at right angles.
TEST(PbrtReference, MeasuredMaterialAnisotropic) { expect_matches_pbrt("mat_measured_aniso"); }
TEST(PbrtReference, MeasuredMaterialByBdlightcuts) {
    expect_matches_pbrt("mat_measured", "bdlightcuts");
}
TEST(PbrtReference, RealisticCamera) { expect_matches_pbrt("camera_realistic"); }
TEST(PbrtReference, RealisticCameraStarAperture) { expect_matches_pbrt("camera_realistic_star"); }
// An image file as the stop: an 8-bit grey L (pbrt-v4 keeps it 8-bit, so unscaled above 1), whose
// pupil is not rotationally symmetric: the exit pupil's rotated bounds cut as much as pbrt-v4's.
TEST(PbrtReference, RealisticCameraImageAperture) { expect_matches_pbrt("camera_realistic_image"); }
TEST(PbrtReference, LoopSubdivShape) { expect_matches_pbrt("shape_loopsubdiv"); }
// A crop window (the EXR's data window inside the display window): by path, by light paths
// splatted into the crop, by bidirectional paths and by a many-light integrator.
TEST(PbrtReference, FilmCropWindow) { expect_matches_pbrt("film_crop"); }
TEST(PbrtReference, FilmCropWindowByLightTracing) {
    expect_matches_pbrt("film_crop", "lighttracer");
}
TEST(PbrtReference, FilmCropWindowByBdpt) { expect_matches_pbrt("film_crop", "bdpt"); }
TEST(PbrtReference, FilmCropWindowByLightcuts) { expect_matches_pbrt("film_crop", "lightcuts"); }
// Alpha on an emitting shape: its emission masked where the cut-out removes it, seen by camera
// rays and sampled by path, and in light paths (lighttracer); by lightcuts, with the light
// sampled and as point lights on the squares that are left.
TEST(PbrtReference, AlphaOnAnAreaLight) { expect_matches_pbrt("light_alpha"); }
TEST(PbrtReference, AlphaOnAnAreaLightByLightTracing) {
    expect_matches_pbrt("light_alpha", "lighttracer");
}
TEST(PbrtReference, AlphaOnAnAreaLightByLightcuts) {
    expect_matches_pbrt("light_alpha", "lightcuts");
    expect_matches_pbrt("light_alpha", "lightcuts", 0, {{"lights.direct", "points"}});
}
// igi at max depth 1: no VPLs (their light would be a second bounce; igi made them, +5.6% here).
TEST(PbrtReference, AlphaOnAnAreaLightByIgi) { expect_matches_pbrt("light_alpha", "igi"); }
// pbrt-v4's invisible light (alpha 0 on an emitter): met by no ray, found by light sampling
// alone (a light sample's MIS weight is 1), by every integrator that starts at the camera and
// at the light; bdlightcuts and mlt refuse it.
TEST(PbrtReference, InvisibleAreaLight) {
    for (const char* integrator : {"path", "bdpt", "lighttracer", "lightcuts", "mdlightcuts"})
        expect_matches_pbrt("light_invisible", integrator);
    // mlt: strategy s = 1 carries the light no path meets, so the bootstrap's paths must be
    // drawn with the density its f / q counts (it was 5.5% bright with the light's solid-angle
    // sample); many chains keep the blocks' noise (correlated along each chain) low.
    expect_matches_pbrt("light_invisible", "mlt", 1024, {{"mlt.chains", "4096"}});
    // bdlightcuts: the last split (the emitter met) by light samples alone, of MIS weight 1;
    // where a setting would leave it to BSDF hits (18% of the light here), it refuses.
    expect_matches_pbrt("light_invisible", "bdlightcuts");
    expect_matches_pbrt("light_invisible", "bdlightcuts", 0, {{"lights.direct", "points"}});
    for (const auto& [key, value] : std::map<std::string, std::string>{
             {"bdlightcuts.emission", "hit"}, {"lights.direct_mis", "glossy"}}) {
        RenderOptions opt;
        opt.progress = false;
        opt.integrator = "bdlightcuts";
        opt.spp = 1;
        opt.set[key] = value;
        EXPECT_THROW(render_scene(parse_scene_file(kScenes + "light_invisible.pbrt"), opt),
                     UsageError)
            << key;
    }
}
// The infinite light's portal: the sky seen and sampled only through a window of a closed room,
// by path; by lightcuts, sampled and as directional point lights drawn from the rectified image.
TEST(PbrtReference, PortalInfiniteLight) { expect_matches_pbrt("light_portal"); }
TEST(PbrtReference, PortalInfiniteLightByLightcuts) {
    expect_matches_pbrt("light_portal", "lightcuts");
    expect_matches_pbrt("light_portal", "lightcuts", 0, {{"lights.direct", "points"}});
}
