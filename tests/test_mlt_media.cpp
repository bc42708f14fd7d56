// Veach's Metropolis light transport (`mlt`) in participating media: paths with medium vertices
// placed by the majorant's collision process, each edge's transmittance in f (estimated, and kept
// with its edge, in grid media), against `path` through a coloured cloud (homogeneous, and a grid
// of varied density) and against `bdpt` on a volumetric caustic in fog, where the lens and
// caustic perturbations move paths through the medium.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "bidir_test_helpers.h"
#include "media_test_helpers.h"

using namespace ml;

namespace {

std::map<std::string, std::string> small_bootstrap() {
    return {{"mlt.bootstrap", "20000"}, {"mlt.chains", "64"}};
}

// Splats spread over a Gaussian lose the part that falls off the film, which the path tracer's
// per-pixel filter weights do not: the comparisons use the box filter.
std::string boxed(const std::string& scene) { return "PixelFilter \"box\"\n" + scene; }

}  // namespace

TEST(MltMedia, AgreesWithPathThroughAColouredCloud) {
    // Coloured coefficients: every medium vertex and edge colours the path, and the chain, which
    // follows luminance, must still give each channel its share.
    const std::string homogeneous = test::coloured_cloud("homogeneous");
    // A grid of varied density: transmittance by ratio tracking, an estimate kept with its edge.
    std::string grid = test::coloured_cloud("uniformgrid");
    const std::string uniform = "\"float density\" [ 1 1 1 1 1 1 1 1 ]";
    ASSERT_NE(grid.find(uniform), std::string::npos);
    grid.replace(grid.find(uniform), uniform.size(),
                 "\"float density\" [ 0.3 2 1 0.5 1.5 0.2 0.8 2.5 ]");
    for (const std::string& scene : {homogeneous, grid}) {
        SCOPED_TRACE(scene.substr(scene.find("MakeNamedMedium"), 60));
        test::expect_agreement(
            test::render_twice(boxed(scene), "mlt", 1024, 4, 16, small_bootstrap(), 8),
            test::render_twice(boxed(scene), "path", 1024, 4, 16), 8,
            "mlt vs path, coloured cloud");
    }
}

TEST(MltMedia, AgreesWithBdptOnAVolumetricCausticInFog) {
    // tests/scenes/media_caustic.pbrt: a spot light focused by a glass sphere into a beam in fog
    // that fills the scene, camera included. Paths E D S S L (the floor's caustic) take caustic
    // perturbations, paths whose first vertex is the floor lens perturbations, every edge
    // through the fog.
    std::ifstream in(MANYLIGHT_SOURCE_DIR "/tests/scenes/media_caustic.pbrt");
    ASSERT_TRUE(in) << "tests/scenes/media_caustic.pbrt";
    std::stringstream text;
    text << in.rdbuf();
    const std::string scene = boxed(text.str());
    test::expect_agreement(test::render_twice(scene, "mlt", 256, 4, 16, small_bootstrap(), 8),
                           test::render_twice(scene, "bdpt", 256, 4, 16), 4,
                           "mlt vs bdpt, volumetric caustic");
}

TEST(MltMedia, SameImageForAnyThreadCount) {
    // The transmittance estimates of the grid's edges draw from each chain's own sampler.
    std::string grid = test::coloured_cloud("uniformgrid");
    auto render = [&](int threads) {
        RenderOptions opt;
        opt.integrator = "mlt";
        opt.spp = 4;
        opt.max_depth = 4;
        opt.width = opt.height = 12;
        opt.threads = threads;
        opt.seed = 3;
        opt.set = small_bootstrap();
        return test::render_text(grid, opt).image;
    };
    const Image a = render(1), b = render(2);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_TRUE(a.pixels[i] == b.pixels[i]) << i;
}
