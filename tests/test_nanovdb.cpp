// pbrt-v4's "nanovdb" medium: grids written here with NanoVDB's own builder and writer, read
// back by the medium (uncompressed, ZIP and Blosc), against Beer's law; the committed grids of
// tests/scenes/media_nanovdb.pbrt and media_fire.pbrt (rendered against pbrt-v4 by
// test_pbrt_reference.cpp) are the ones smoke_grid() and fire_grids() build; and what the medium
// refuses.
#include <gtest/gtest.h>
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "majorant_check.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;
using namespace ml::test;

namespace {

const std::string kScenes = MANYLIGHT_SOURCE_DIR "/tests/scenes/";

using Handle = nanovdb::GridHandle<nanovdb::HostBuffer>;

// A fog volume named `name` of voxels `voxel` wide, index [lo, hi]^3 from the world origin,
// each voxel's density f(world centre); zeros stay inactive.
template <class F>
Handle fog_grid(int lo, int hi, double voxel, const F& f, const std::string& name = "density") {
    nanovdb::GridBuilder<float> builder(0.f, nanovdb::GridClass::FogVolume);
    builder(
        [&](const nanovdb::Coord& ijk) {
            return f(voxel * ijk[0], voxel * ijk[1], voxel * ijk[2]);
        },
        nanovdb::CoordBBox(nanovdb::Coord(lo), nanovdb::Coord(hi)));
    return builder.getHandle<>(voxel, nanovdb::Vec3d(0), name);
}

// The smoke of media_nanovdb.pbrt: a ball of radius 0.9 about (0, 1, 0), thinning outwards,
// modulated by waves; 24^3 voxels over [-1, 1] x [0, 2] x [-1, 1].
Handle smoke_grid() {
    nanovdb::GridBuilder<float> builder(0.f, nanovdb::GridClass::FogVolume);
    const double voxel = 2.0 / 24;
    builder(
        [&](const nanovdb::Coord& ijk) {
            const double x = -1 + voxel * (ijk[0] + 0.5), y = voxel * (ijk[1] + 0.5),
                         z = -1 + voxel * (ijk[2] + 0.5);
            const double r = std::sqrt(x * x + (y - 1) * (y - 1) + z * z);
            const double wave = 0.7 + 0.3 * std::sin(3 * x) * std::sin(4 * y + 1) * std::cos(5 * z);
            return float(std::max(0.0, 1 - r / 0.9) * wave * 2);
        },
        nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(23)));
    return builder.getHandle<>(voxel, nanovdb::Vec3d(-1, 0, -1), "density");
}

// The fire of media_fire.pbrt: a ball of radius 0.9 about (0, 1, 0) on the same 24^3 voxels,
// its density falling outwards and its temperature from 3500 K at the centre to 1000 K at the
// rim ("temperature", in the same file).
std::vector<Handle> fire_grids() {
    const double voxel = 2.0 / 24;
    auto ball = [&](const nanovdb::Coord& ijk) {
        const double x = -1 + voxel * (ijk[0] + 0.5), y = voxel * (ijk[1] + 0.5),
                     z = -1 + voxel * (ijk[2] + 0.5);
        return std::max(0.0, 1 - std::sqrt(x * x + (y - 1) * (y - 1) + z * z) / 0.9);
    };
    const nanovdb::CoordBBox box(nanovdb::Coord(0), nanovdb::Coord(23));
    nanovdb::GridBuilder<float> density(0.f, nanovdb::GridClass::FogVolume);
    density([&](const nanovdb::Coord& ijk) { return float(ball(ijk)); }, box);
    nanovdb::GridBuilder<float> temperature(0.f, nanovdb::GridClass::FogVolume);
    temperature(
        [&](const nanovdb::Coord& ijk) {
            const double b = ball(ijk);
            return b > 0 ? float(1000 + 2500 * b) : 0.f;
        },
        box);
    std::vector<Handle> grids;
    grids.push_back(density.getHandle<>(voxel, nanovdb::Vec3d(-1, 0, -1), "density"));
    grids.push_back(temperature.getHandle<>(voxel, nanovdb::Vec3d(-1, 0, -1), "temperature"));
    return grids;
}

// `made` and `read` hold the same values over the index box [lo, hi]^3; the count of positive
// ones.
int expect_same_grid(const Handle& made, const Handle& read, int lo, int hi) {
    const auto *a = made.grid<float>(), *b = read.grid<float>();
    EXPECT_TRUE(a && b);
    if (!a || !b) return 0;
    EXPECT_TRUE(b->isFogVolume());
    auto acc_a = a->getAccessor();
    auto acc_b = b->getAccessor();
    int positive = 0;
    for (int i = lo; i <= hi; ++i)
        for (int j = lo; j <= hi; ++j)
            for (int k = lo; k <= hi; ++k) {
                const nanovdb::Coord ijk(i, j, k);
                EXPECT_EQ(acc_a.getValue(ijk), acc_b.getValue(ijk)) << i << " " << j << " " << k;
                positive += acc_b.getValue(ijk) > 0;
            }
    return positive;
}

}  // namespace

TEST(NanoVdb, ACompressedOrPlainGridTransmitsAsBeersLaw) {
    // An orthographic camera inside a grid of density 1 over [-10, 10]^3 (voxels 0.5 wide),
    // sigma_a (0.5, 1, 2) times "scale" 0.5, looking at an emitter 2 away: exp(-2 sigma_a).
    ScratchDir dir;
    const Handle grid = fog_grid(-20, 20, 0.5, [](double, double, double) { return 1.f; });
    for (auto codec :
         {nanovdb::io::Codec::NONE, nanovdb::io::Codec::ZIP, nanovdb::io::Codec::BLOSC}) {
        SCOPED_TRACE(nanovdb::io::toStr(codec));
        nanovdb::io::writeGrid(dir.file("g.nvdb"), grid, codec);
        const std::string scene =
            "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"g.nvdb\"\n"
            "  \"rgb sigma_a\" [ 1 2 4 ] \"rgb sigma_s\" [ 0 0 0 ] \"float scale\" [ 0.5 ]\n"
            "MediumInterface \"\" \"m\"\nLookAt 0 0 0  0 0 1  0 1 0\nCamera \"orthographic\"\n"
            "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\n"
            "Sampler \"independent\"\nIntegrator \"path\"\nWorldBegin\n"
            "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n"
            "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
            "  \"point3 P\" [ -5 -5 2  -5 5 2  5 5 2  5 -5 2 ]\n";
        RenderOptions opt;
        opt.spp = 256;
        opt.seed = 3;
        const Image img =
            render_scene(parse_scene_string(scene, dir.path(), "test.pbrt"), opt).image;
        const double sigma[3] = {0.5, 1, 2};
        for (int c = 0; c < 3; ++c) {
            const ChannelStats s = channel_stats(img, c);
            EXPECT_NEAR(s.mean, std::exp(-2 * sigma[c]), 4 * s.stderr_of_mean + 1e-6) << c;
            EXPECT_NEAR(s.mean, std::exp(-2 * sigma[c]), 0.05 * std::exp(-2 * sigma[c])) << c;
        }
    }
}

TEST(NanoVdb, TheReferenceScenesGridsAreTheSmokeAndTheFire) {
    // MANYLIGHT_WRITE_NVDB=1 writes them, ZIP-compressed (how tests/scenes/media_nanovdb.nvdb and
    // media_fire.nvdb were made).
    const std::string smoke = kScenes + "media_nanovdb.nvdb", fire = kScenes + "media_fire.nvdb";
    const Handle made = smoke_grid();
    const std::vector<Handle> made_fire = fire_grids();
    if (std::getenv("MANYLIGHT_WRITE_NVDB")) {
        nanovdb::io::writeGrid(smoke, made, nanovdb::io::Codec::ZIP);
        nanovdb::io::writeGrids(fire, made_fire, nanovdb::io::Codec::ZIP);
    }
    EXPECT_GT(expect_same_grid(made, nanovdb::io::readGrid(smoke, "density"), -1, 24), 3000);
    EXPECT_GT(expect_same_grid(made_fire[0], nanovdb::io::readGrid(fire, "density"), -1, 24), 2000);
    EXPECT_GT(expect_same_grid(made_fire[1], nanovdb::io::readGrid(fire, "temperature"), -1, 24),
              2000);
}

TEST(NanoVdb, ItsMajorantCellsBoundTheSmokeAlongEveryRay) {
    // The smoke under a rotation: the 64^3 majorant cells straddle its voxels; along random rays
    // the segments adjoin and bound sigma_a + sigma_s at every point tried, and the empty corners
    // of its box get lower bounds than the whole.
    ScratchDir dir;
    nanovdb::io::writeGrid(dir.file("smoke.nvdb"), smoke_grid());
    const SceneDesc desc = parse_scene_string(
        "Rotate 25 1 1 0\nMakeNamedMedium \"m\" \"string type\" \"nanovdb\" "
        "\"string filename\" \"smoke.nvdb\"\n  \"rgb sigma_a\" [ 1 2 3 ] "
        "\"rgb sigma_s\" [ 2 1 1 ]\nWorldBegin\n",
        dir.path(), "test.pbrt");
    const double saved =
        expect_majorants_bound(*desc.media[0], Vec3(-2, -1, -2), Vec3(2, 3, 2), 2000, 21);
    EXPECT_GT(saved, 0.2);
}

TEST(NanoVdb, WhatItCannotReadSaysSo) {
    ScratchDir dir;
    const std::string head = "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" ";
    expect_input_error([&] { parse_scene_string(head + "\n", dir.path(), "test.pbrt"); },
                       "test.pbrt", 1, 1, "no \"string filename\"");
    expect_input_error(
        [&] {
            parse_scene_string(head + "\"string filename\" \"none.nvdb\"\n", dir.path(),
                               "test.pbrt");
        },
        "test.pbrt", 1, 45, "no file");
    dir.write("junk.nvdb", "not a grid at all");
    expect_input_error(
        [&] {
            parse_scene_string(head + "\"string filename\" \"junk.nvdb\"\n", dir.path(),
                               "test.pbrt");
        },
        "test.pbrt", 1, 45, "cannot read \"density\"");
    nanovdb::io::writeGrid(dir.file("other.nvdb"),
                           fog_grid(
                               0, 3, 1, [](double, double, double) { return 1.f; }, "smoke"));
    expect_input_error(
        [&] {
            parse_scene_string(head + "\"string filename\" \"other.nvdb\"\n", dir.path(),
                               "test.pbrt");
        },
        "test.pbrt", 1, 45, "has no grid \"density\"");
    // A "temperature" grid that does not hold floats.
    nanovdb::GridBuilder<double> doubles(0.0, nanovdb::GridClass::FogVolume);
    doubles([](const nanovdb::Coord&) { return 900.0; },
            nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(3)));
    std::vector<Handle> both;
    both.push_back(fog_grid(0, 3, 1, [](double, double, double) { return 1.f; }));
    both.push_back(doubles.getHandle<>(1.0, nanovdb::Vec3d(0), "temperature"));
    nanovdb::io::writeGrids(dir.file("fire.nvdb"), both);
    expect_input_error(
        [&] {
            parse_scene_string(head + "\"string filename\" \"fire.nvdb\"\n", dir.path(),
                               "test.pbrt");
        },
        "test.pbrt", 1, 45, "grid \"temperature\" of");
}
