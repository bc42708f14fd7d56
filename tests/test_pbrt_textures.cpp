// pbrt-v4's texture mappings and the checkerboard texture: the mappings against their formulas
// at chosen points, and tests/scenes/checkerboard.pbrt rendered against its analytic image
// (each pixel's radiance is the albedo of its square), also with the same board made by the
// "planar" mapping and by a 3D checkerboard.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "materials/create.h"
#include "materials/textures.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;
using ml::test::expect_scene_error;

namespace {

TextureEvalContext at(Vec3 p, Vec2 uv = Vec2(0, 0)) { return {p, uv}; }

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const std::string kBoardScene = MANYLIGHT_SOURCE_DIR "/tests/scenes/checkerboard.pbrt";

// The checkerboard scene with its Texture directive replaced by `texture`.
std::string board_scene_with(const std::string& texture) {
    std::string text = read_text(kBoardScene);
    size_t a = text.find("Texture \"checks\"");
    size_t b = text.find('\n', a);
    EXPECT_NE(a, std::string::npos);
    return text.replace(a, b - a, texture);
}

// Every pixel is the albedo of the square it lies in: 8 x 8 pixels per square, tex1 (0.8) on
// the square at world (-1, -1), which pbrt-v4's LookAt puts at the bottom right of the image.
void expect_board(const Image& img) {
    ASSERT_EQ(img.width, 64);
    ASSERT_EQ(img.height, 64);
    double sum = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            // Image x runs along world -x, image y along world -y.
            int i = 7 - x / 8, j = 7 - y / 8;
            float expected = (i + j) % 2 == 0 ? 0.8f : 0.2f;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(img.at(x, y)[c], expected, 2e-3f) << "pixel " << x << "," << y;
            sum += img.at(x, y).g;
        }
    EXPECT_NEAR(sum / (64 * 64), 0.5, 1e-3);  // the mean albedo: (tex1 + tex2) / 2
}

RenderOutput render_board(const std::string& text) {
    RenderOptions opt;
    opt.progress = false;
    return render_scene(parse_scene_string(text, ".", "checkerboard.pbrt"), opt);
}

}  // namespace

TEST(TextureMapping, UVScalesAndShifts) {
    TextureMapping2D m;
    m.su = 2, m.sv = 3, m.du = 0.5f, m.dv = -1;
    Vec2 st = m.map(at(Vec3(9, 9, 9), Vec2(0.25f, 0.5f)));
    EXPECT_FLOAT_EQ(st.x, 1.f);
    EXPECT_FLOAT_EQ(st.y, 0.5f);
}

TEST(TextureMapping, SphericalIsThetaAndPhiOverPi) {
    TextureMapping2D m;
    m.kind = TextureMapping2D::Kind::Spherical;
    // Texture space moved by +1 in x: the world point (1, 0, 2) is straight up (theta 0).
    m.world_to_texture = Transform::translate(Vec3(1, 0, 0)).inverse();
    EXPECT_NEAR(m.map(at(Vec3(1, 0, 2))).x, 0.f, 1e-6f);
    // (1, 1, 0) in texture space: theta = pi/2, phi = pi/4.
    Vec2 st = m.map(at(Vec3(2, 1, 0)));
    EXPECT_NEAR(st.x, 0.5f, 1e-6f);
    EXPECT_NEAR(st.y, 0.125f, 1e-6f);
    // (0, -1, -1): theta = 3pi/4, phi = 3pi/2.
    st = m.map(at(Vec3(1, -1, -1)));
    EXPECT_NEAR(st.x, 0.75f, 1e-6f);
    EXPECT_NEAR(st.y, 0.75f, 1e-6f);
}

TEST(TextureMapping, CylindricalIsAngleAndHeight) {
    TextureMapping2D m;
    m.kind = TextureMapping2D::Kind::Cylindrical;
    Vec2 st = m.map(at(Vec3(1, 0, 0.3f)));  // atan2 = 0: s = 1/2
    EXPECT_NEAR(st.x, 0.5f, 1e-6f);
    EXPECT_FLOAT_EQ(st.y, 0.3f);
    st = m.map(at(Vec3(0, -2, -4)));  // atan2 = -pi/2: s = 1/4
    EXPECT_NEAR(st.x, 0.25f, 1e-6f);
    EXPECT_FLOAT_EQ(st.y, -4.f);
}

TEST(TextureMapping, PlanarProjectsOnV1AndV2) {
    TextureMapping2D m;
    m.kind = TextureMapping2D::Kind::Planar;
    m.v1 = Vec3(1, 1, 0), m.v2 = Vec3(0, 0, 2), m.du = 0.5f, m.dv = 1;
    Vec2 st = m.map(at(Vec3(1, 2, 3)));
    EXPECT_FLOAT_EQ(st.x, 3.5f);
    EXPECT_FLOAT_EQ(st.y, 7.f);
}

TEST(Checkerboard, ParityOfTheSquares) {
    Checkerboard b;
    EXPECT_FALSE(b.second(at(Vec3(), Vec2(0.5f, 0.5f))));
    EXPECT_TRUE(b.second(at(Vec3(), Vec2(1.5f, 0.5f))));
    EXPECT_FALSE(b.second(at(Vec3(), Vec2(-0.5f, -0.5f))));
    EXPECT_TRUE(b.second(at(Vec3(), Vec2(-0.5f, 0.5f))));
    b.dimension = 3;
    EXPECT_FALSE(b.second(at(Vec3(0.5f, 0.5f, 0.5f))));
    EXPECT_TRUE(b.second(at(Vec3(0.5f, 0.5f, 1.5f))));
    EXPECT_FALSE(b.second(at(Vec3(-0.5f, 0.5f, 1.5f))));
}

TEST(Checkerboard, DefaultsAreOneAndZero) {
    NamedTextures textures;
    ImageCache images;
    ParameterList none;
    create_texture("c", "float", "checkerboard", none, "", textures, images, {});
    const FloatTexture& t = *textures.floats.at("c");
    EXPECT_EQ(t.eval(at(Vec3(), Vec2(0.5f, 0.5f))), 1.f);
    EXPECT_EQ(t.eval(at(Vec3(), Vec2(1.5f, 0.5f))), 0.f);
}

TEST(Checkerboard, FloorRendersItsSquares) {
    expect_board(render_board(read_text(kBoardScene)).image);
}

TEST(Checkerboard, PlanarMappingMakesTheSameFloor) {
    // s = 4x, t = 4y over [-1, 1]^2: the same 8 x 8 squares, the one at (-1, -1) even.
    expect_board(
        render_board(board_scene_with("Texture \"checks\" \"spectrum\" \"checkerboard\" "
                                      "\"string mapping\" \"planar\" \"vector3 v1\" [ 4 0 0 ] "
                                      "\"vector3 v2\" [ 0 4 0 ] \"rgb tex1\" [ 0.8 0.8 0.8 ] "
                                      "\"rgb tex2\" [ 0.2 0.2 0.2 ]"))
            .image);
}

TEST(Checkerboard, ThreeDimensionalInItsOwnSpaceMakesTheSameFloor) {
    // Texture space scaled by 1/4 at the directive: squares of 1/4, and the floor at z = 0.1
    // lies in the layer floor(4 z) = 0.
    expect_board(
        render_board(board_scene_with("AttributeBegin\nScale 0.25 0.25 0.25\n"
                                      "Texture \"checks\" \"spectrum\" \"checkerboard\" "
                                      "\"integer dimension\" [ 3 ] \"rgb tex1\" [ 0.8 0.8 0.8 ] "
                                      "\"rgb tex2\" [ 0.2 0.2 0.2 ]\nAttributeEnd"))
            .image);
}

TEST(Checkerboard, BadInputIsReportedAtItsPlace) {
    expect_scene_error(
        "WorldBegin\nTexture \"c\" \"float\" \"checkerboard\"\n  \"integer dimension\" [ 4 ]\n", 3,
        3, "\"dimension\" must be 2 or 3");
    expect_scene_error(
        "WorldBegin\nTexture \"c\" \"float\" \"checkerboard\" \"string mapping\" \"cubic\"\n", 2,
        36, "unknown texture mapping \"cubic\"");
    expect_scene_error(
        "WorldBegin\nTexture \"c\" \"float\" \"checkerboard\"\n  \"texture tex1\" \"nope\"\n", 3, 3,
        "undefined float texture \"nope\"");
    // Mapping parameters belong to textures that map; "constant" does not.
    expect_scene_error(
        "WorldBegin\nTexture \"c\" \"float\" \"constant\"\n  \"float uscale\" [ 2 ]\n", 3, 3,
        "unknown or unused");
    // The planar mapping has no scale: pbrt-v4 reports "uscale" there as unused.
    expect_scene_error(
        "WorldBegin\nTexture \"c\" \"float\" \"checkerboard\" \"string mapping\" \"planar\"\n"
        "  \"float uscale\" [ 2 ]\n",
        3, 3, "unknown or unused");
}
