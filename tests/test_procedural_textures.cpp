// pbrt-v4's procedural textures (bilerp, dots, fbm, wrinkled, windy, marble, mix, directionmix)
// and the Perlin noise under them, by properties that do not depend on the noise's table: zero
// on the lattice, gradients along the cube's edges there, period 256, octave sums built from
// single octaves, dots that are whole disks inside their cells. tests/test_pbrt_reference.cpp
// compares their renders with pbrt-v4's.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "core/noise.h"
#include "materials/procedural_textures.h"
#include "parser_test_helpers.h"
#include "scene/scene_desc.h"

using namespace ml;
using ml::test::expect_scene_error;

namespace {

TextureEvalContext at(Vec3 p, Vec2 uv = Vec2(0, 0), Vec3 n = Vec3(0, 0, 1)) { return {p, uv, n}; }

// The textures a scene's world block defines.
NamedTextures textures_of(const std::string& world) {
    return parse_scene_string("WorldBegin\n" + world, ".", "test.pbrt").textures;
}

const Vec3 kPoints[] = {
    {0.3f, 0.7f, 0.1f}, {-2.6f, 5.2f, 0.9f}, {13.1f, -7.45f, 3.3f}, {100.5f, 0.25f, -40.8f}};

}  // namespace

TEST(PerlinNoise, ZeroOnTheLatticeWithGradientsAlongCubeEdges) {
    std::set<std::tuple<int, int, int>> seen;
    for (int x = -3; x <= 3; ++x)
        for (int y = -3; y <= 3; ++y)
            for (int z = -3; z <= 3; ++z) {
                EXPECT_EQ(perlin_noise(float(x), float(y), float(z)), 0.f);
                // The slope at the corner is its gradient: two components +-1, one 0 (the
                // fade's zero derivative leaves only the corner's own ramp).
                const float e = 1e-3f;
                Vec3 g(perlin_noise(x + e, float(y), float(z)) / e,
                       perlin_noise(float(x), y + e, float(z)) / e,
                       perlin_noise(float(x), float(y), z + e) / e);
                int ones = 0, zeros = 0;
                for (int c = 0; c < 3; ++c) {
                    ones += std::abs(std::abs(g[c]) - 1) < 0.01f;
                    zeros += std::abs(g[c]) < 0.01f;
                }
                EXPECT_EQ(ones, 2) << x << " " << y << " " << z;
                EXPECT_EQ(zeros, 1) << x << " " << y << " " << z;
                seen.insert({int(std::round(g.x)), int(std::round(g.y)), int(std::round(g.z))});
            }
    EXPECT_EQ(seen.size(), 12u);  // every edge direction occurs
}

TEST(PerlinNoise, PeriodicContinuousAndBounded) {
    double sum = 0, sum2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Vec3 p(std::fmod(i * 0.6180339f, 50.f), std::fmod(i * 0.4142135f, 50.f),
               std::fmod(i * 0.7320508f, 50.f));
        float v = perlin_noise(p);
        ASSERT_LE(std::abs(v), 1.1f);
        // Period 256 along each axis (the permutation's length).
        EXPECT_NEAR(perlin_noise(p + Vec3(256, 0, 0)), v, 2e-4f);
        EXPECT_NEAR(perlin_noise(p + Vec3(0, -256, 512)), v, 2e-4f);
        // Continuous: a step of 1e-4 moves it by at most a few times that.
        EXPECT_NEAR(perlin_noise(p + Vec3(1e-4f, 1e-4f, 1e-4f)), v, 1e-3f);
        sum += v;
        sum2 += double(v) * v;
    }
    EXPECT_NEAR(sum / n, 0, 0.02);  // symmetric gradients: mean zero
    EXPECT_GT(sum2 / n, 0.01);      // and not flat
    EXPECT_EQ(perlin_noise(Vec3(1e9f, 2e9f, -3e9f)), perlin_noise(Vec3(1e9f, 2e9f, -3e9f)));
}

TEST(PerlinNoise, OctaveSumsAreMadeOfSingleOctaves) {
    for (const Vec3& p : kPoints) {
        // With every octave (no footprint), fbm is the sum of omega^i noise(1.99^i p).
        float sum = 0, o = 1, lambda = 1, tsum = 0;
        for (int i = 0; i < 5; ++i) {
            sum += o * perlin_noise(p * lambda);
            tsum += o * std::abs(perlin_noise(p * lambda));
            lambda *= 1.99f;
            o *= 0.6f;
        }
        EXPECT_NEAR(fbm(p, 0, 0.6f, 5), sum, 1e-5f);
        // Turbulence adds the mean of |noise| (0.2) for the octave after the last.
        EXPECT_NEAR(turbulence(p, 0, 0.6f, 5), tsum + 0.2f * o, 1e-5f);
    }
    // The octave count for a footprint: -1 - log2(footprint^2) / 2, clamped.
    EXPECT_FLOAT_EQ(noise_octaves(0, 8), 8);
    EXPECT_FLOAT_EQ(noise_octaves(std::pow(2.f, -10.f), 8), 4);
    EXPECT_FLOAT_EQ(noise_octaves(std::pow(2.f, -30.f), 8), 8);
    EXPECT_FLOAT_EQ(noise_octaves(4, 8), 0);
    // With a footprint of 2^-5 (4 octaves), the fifth is left out and the rest as above.
    const Vec3 p = kPoints[1];
    EXPECT_NEAR(fbm(p, std::pow(2.f, -10.f), 0.5f, 8),
                perlin_noise(p) + 0.5f * perlin_noise(p * 1.99f) +
                    0.25f * perlin_noise(p * 1.99f * 1.99f) +
                    0.125f * perlin_noise(p * 1.99f * 1.99f * 1.99f),
                1e-5f);
}

TEST(ProceduralTextures, NoiseTexturesReadTheTextureSpacePoint) {
    // Texture space scaled by 1/4 at the directive: the texture at world p is noise at 4p.
    NamedTextures t = textures_of(
        "AttributeBegin\nScale 0.25 0.25 0.25\n"
        "Texture \"f\" \"float\" \"fbm\" \"integer octaves\" [ 3 ] \"float roughness\" [ 0.4 ]\n"
        "Texture \"w\" \"float\" \"wrinkled\"\n"
        "Texture \"y\" \"float\" \"windy\"\nAttributeEnd\n");
    for (const Vec3& p : kPoints) {
        Vec3 q = p * 4;
        EXPECT_NEAR(t.floats.at("f")->eval(at(p)), fbm(q, 0, 0.4f, 3), 1e-5f);
        EXPECT_NEAR(t.floats.at("w")->eval(at(p)), turbulence(q, 0, 0.5f, 8), 1e-5f);
        EXPECT_NEAR(t.floats.at("y")->eval(at(p)),
                    std::abs(fbm(q * 0.1f, 0, 0.5f, 3)) * fbm(q, 0, 0.5f, 6), 1e-5f);
    }
}

TEST(ProceduralTextures, BilerpIsExactAtTheCornersAndLinearAlongEdges) {
    NamedTextures t = textures_of(
        "Texture \"b\" \"float\" \"bilerp\" \"float v00\" [ 1 ] \"float v10\" [ 2 ] "
        "\"float v01\" [ 3 ] \"float v11\" [ 5 ]\n"
        "Texture \"c\" \"spectrum\" \"bilerp\" \"float uscale\" [ 2 ]\n");
    const FloatTexture& b = *t.floats.at("b");
    EXPECT_FLOAT_EQ(b.eval(at({}, Vec2(0, 0))), 1);
    EXPECT_FLOAT_EQ(b.eval(at({}, Vec2(1, 0))), 2);
    EXPECT_FLOAT_EQ(b.eval(at({}, Vec2(0, 1))), 3);
    EXPECT_FLOAT_EQ(b.eval(at({}, Vec2(1, 1))), 5);
    EXPECT_FLOAT_EQ(b.eval(at({}, Vec2(0.5f, 0))), 1.5f);
    EXPECT_FLOAT_EQ(b.eval(at({}, Vec2(0.5f, 0.5f))), 2.75f);
    // Defaults v00 = v10 = 0, v01 = v11 = 1: t alone; uscale leaves it unchanged.
    EXPECT_FLOAT_EQ(t.rgbs.at("c")->eval(at({}, Vec2(0.3f, 0.25f))).g, 0.25f);
}

TEST(ProceduralTextures, DotsAreWholeDisksInsideTheirCells) {
    // Each unit cell around an integer (s, t) holds one disk of radius 0.35 or none, so the
    // share of a cell's points inside is 0 or pi 0.35^2; "outside" shows inside the dots
    // (pbrt-v4's swap).
    NamedTextures t = textures_of(
        "Texture \"d\" \"float\" \"dots\" \"float inside\" [ 0.25 ] \"float outside\" [ 0.75 ]\n");
    const FloatTexture& d = *t.floats.at("d");
    int with_dot = 0;
    const int n = 64;
    for (int cs = -6; cs < 6; ++cs)
        for (int ct = -6; ct < 6; ++ct) {
            int in = 0;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    Vec2 st(cs - 0.5f + (i + 0.5f) / n, ct - 0.5f + (j + 0.5f) / n);
                    bool inside = inside_polka_dot(st);
                    in += inside;
                    ASSERT_EQ(d.eval(at({}, st)), inside ? 0.75f : 0.25f);
                }
            double share = double(in) / (n * n);
            if (in == 0) continue;
            ++with_dot;
            EXPECT_NEAR(share, kPi * 0.35 * 0.35, 0.01) << cs << " " << ct;
        }
    EXPECT_GT(with_dot, 144 / 5);  // about half the cells (where the noise is positive)
    EXPECT_LT(with_dot, 144 * 4 / 5);
}

TEST(ProceduralTextures, MarbleStaysInItsColoursAndRepeatsAlongY) {
    // Without variation the bands are sin(scale y): period 2 pi / scale along texture y.
    NamedTextures t = textures_of(
        "Texture \"m\" \"spectrum\" \"marble\" \"float scale\" [ 2 ] \"float variation\" [ 0 ]\n"
        "Texture \"v\" \"spectrum\" \"marble\"\n");
    const RGBTexture& m = *t.rgbs.at("m");
    for (const Vec3& p : kPoints) {
        RGB a = m.eval(at(p)), b = m.eval(at(p + Vec3(0, kPi, 0)));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-4f);
        RGB c = m.eval(at(p + Vec3(5, 0, -3)));  // nothing changes across the bands
        EXPECT_NEAR(c.g, a.g, 1e-5f);
        // 1.5 times a Bezier of colours in [0.2, 0.6]: inside [0.3, 0.9].
        RGB v = t.rgbs.at("v")->eval(at(p));
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(v[k], 0.3f - 1e-5f);
            EXPECT_LE(v[k], 0.9f + 1e-5f);
        }
    }
}

TEST(ProceduralTextures, MixBlendsByAmountAndDirectionMixByTheNormal) {
    NamedTextures t = textures_of(
        "Texture \"a\" \"float\" \"bilerp\" \"float v00\" [ 0 ] \"float v10\" [ 1 ] "
        "\"float v01\" [ 0 ] \"float v11\" [ 1 ]\n"
        "Texture \"m\" \"spectrum\" \"mix\" \"rgb tex1\" [ 0.2 0.4 0.6 ] \"rgb tex2\" [ 1 1 1 ] "
        "\"texture amount\" \"a\"\n"
        "Texture \"f\" \"float\" \"mix\"\n"
        "AttributeBegin\nRotate 90 0 0 1\n"
        "Texture \"d\" \"float\" \"directionmix\" \"float tex1\" [ 4 ] \"float tex2\" [ 2 ] "
        "\"vector3 dir\" [ 1 0 0 ]\nAttributeEnd\n");
    RGB m = t.rgbs.at("m")->eval(at({}, Vec2(0.25f, 0.9f)));
    EXPECT_NEAR(m.r, 0.75f * 0.2f + 0.25f, 1e-6f);
    EXPECT_NEAR(m.b, 0.75f * 0.6f + 0.25f, 1e-6f);
    EXPECT_FLOAT_EQ(t.floats.at("f")->eval(at({})), 0.5f);  // defaults: 0, 1, amount 0.5
    // dir (1, 0, 0) in texture space rotated 90 degrees about z: world +y.
    const FloatTexture& d = *t.floats.at("d");
    EXPECT_NEAR(d.eval(at({}, {}, Vec3(0, 1, 0))), 4, 1e-5f);
    EXPECT_NEAR(d.eval(at({}, {}, Vec3(0, -1, 0))), 4, 1e-5f);
    EXPECT_NEAR(d.eval(at({}, {}, Vec3(1, 0, 0))), 2, 1e-5f);
    EXPECT_NEAR(d.eval(at({}, {}, Vec3(0, 0.5f, std::sqrt(0.75f)))), 3, 1e-5f);
}

TEST(ProceduralTextures, WrongKindsAndBadValuesAreErrors) {
    expect_scene_error("WorldBegin\nTexture \"n\" \"spectrum\" \"fbm\"\n", 2, 1,
                       "\"fbm\" is a float texture in pbrt-v4");
    expect_scene_error("WorldBegin\nTexture \"n\" \"float\" \"marble\"\n", 2, 1,
                       "\"marble\" is a spectrum texture in pbrt-v4");
    expect_scene_error(
        "WorldBegin\nTexture \"n\" \"float\" \"wrinkled\" \"integer octaves\" [ 0 ]\n", 2, 32,
        "\"octaves\" must lie in [1, 32]");
    expect_scene_error("WorldBegin\nTexture \"n\" \"float\" \"ptex\"\n", 2, 1, "not supported");
    expect_scene_error("WorldBegin\nTexture \"n\" \"float\" \"windy\" \"float roughness\" [ 1 ]\n",
                       2, 29, "\"float roughness\" is unknown or unused");
}
