// Bad scene input: one test per case, each checking the error's file, line, column and message.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "parser_test_helpers.h"
#include "ply_test_helpers.h"
#include "shared_files.h"

using namespace ml;
using ml::test::expect_input_error;
using ml::test::expect_scene_error;
using ml::test::ScratchDir;

TEST(BadInput, UnterminatedString) {
    expect_scene_error("WorldBegin\nShape \"sphere\n", 2, 7, "unterminated string");
    expect_scene_error("Film \"rgb\" \"string filename\" \"out.exr", 1, 30, "unterminated string");
}

TEST(BadInput, UnexpectedToken) {
    expect_scene_error("WorldBegin\n  [ 1 2 ]\n", 2, 3, "expected a directive");
    expect_scene_error("Translate 1 2 \"3\"\n", 1, 15, "expects a number");
    expect_scene_error("Transform 1 0 0 0\n", 1, 11, "expects '['");
    expect_scene_error("Film \"rgb\" \"integer xresolution\" [ 4 \n", 1, 34,
                       "without a matching ']'");
}

TEST(BadInput, BadNumber) {
    expect_scene_error("Translate 1 2x 3\n", 1, 13, "bad number '2x'");
    expect_scene_error("Film \"rgb\" \"float iso\" [ 1..5 ]\n", 1, 26, "bad number '1..5'");
    expect_scene_error("Translate 1 inf 3\n", 1, 13, "bad number 'inf'");
    expect_scene_error("Translate 1 0 1e999\n", 1, 15, "bad number '1e999'");
}

TEST(BadInput, IntegerParameterWithFraction) {
    expect_scene_error("Film \"rgb\" \"integer xresolution\" 6.5\n", 1, 34, "expects integers");
}

TEST(BadInput, UnknownDirective) {
    expect_scene_error("WorldBegin\n\n  Shapes \"sphere\"\n", 3, 3, "unknown directive \"Shapes\"");
}

TEST(BadInput, UnknownShape) {
    expect_scene_error("WorldBegin\nShape \"cube\"\n", 2, 1, "unknown shape \"cube\"");
}

TEST(BadInput, UnknownMaterialType) {
    expect_scene_error("WorldBegin\nMaterial \"no-such-material\"\n", 2, 1, "no-such-material");
}

TEST(BadInput, UnknownLightType) {
    expect_scene_error("WorldBegin\nLightSource \"no-such-light\"\n", 2, 1, "no-such-light");
}

TEST(BadInput, UnusedShapeParameter) {
    expect_scene_error("WorldBegin\nShape \"sphere\" \"float radius\" 1\n   \"float bogus\" 2\n", 3,
                       4, "\"float bogus\" is unknown or unused");
}

TEST(BadInput, UnknownParameterType) {
    expect_scene_error("WorldBegin\nShape \"sphere\" \"flaot radius\" 1\n", 2, 16,
                       "unknown parameter type \"flaot\"");
}

TEST(BadInput, ParameterOfWrongType) {
    expect_scene_error(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"float indices\" [0 "
        "1 2]\n",
        2, 53, "has type \"float\"");
}

TEST(BadInput, ParameterOfWrongArity) {
    expect_scene_error("WorldBegin\nShape \"sphere\" \"float radius\" [1 2]\n", 2, 16,
                       "needs 1 value");
}

TEST(BadInput, UndefinedNamedMaterial) {
    expect_scene_error("WorldBegin\n  NamedMaterial \"nope\"\n", 2, 3,
                       "undefined named material \"nope\"");
}

TEST(BadInput, RedefinedNamedMaterial) {
    expect_scene_error(
        "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
        "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n",
        3, 1, "redefined");
}

TEST(BadInput, UndefinedTexture) {
    // The material factory reports it, at the directive or at the parameter.
    try {
        parse_scene_string(
            "WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"no-such-texture\"\n", ".",
            "test.pbrt");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.loc().file, "test.pbrt");
        EXPECT_EQ(e.loc().line, 2);
        EXPECT_TRUE(e.loc().column == 1 || e.loc().column == 20) << e.formatted();
        EXPECT_NE(std::string(e.what()).find("no-such-texture"), std::string::npos) << e.what();
    }
}

TEST(BadInput, UnreadableTexture) {
    ScratchDir dir;
    dir.write("garbage.png", "this is not an image");
    std::filesystem::create_directories(dir.file("folder.png"));
    for (const char* name : {"garbage.png", "folder.png", "missing.png"}) {
        try {
            parse_scene_string(std::string("WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" "
                                           "\"string filename\" \"") +
                                   name + "\"\n",
                               dir.path(), "test.pbrt");
            ADD_FAILURE() << "no error for " << name;
        } catch (const InputError& e) {
            // At the directive, at the parameter, or in the image file itself.
            if (e.loc().file == "test.pbrt") {
                EXPECT_EQ(e.loc().line, 2) << e.formatted();
                EXPECT_TRUE(e.loc().column == 1 || e.loc().column == 35) << e.formatted();
            } else {
                EXPECT_NE(e.loc().file.find(name), std::string::npos) << e.formatted();
            }
        }
    }
}

TEST(BadInput, MissingInclude) {
    ScratchDir dir;
    std::string main = dir.write("scene.pbrt", "WorldBegin\n\n  Include \"nothere.pbrt\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 3, 3, "no such file");
}

TEST(BadInput, IncludeOfADirectory) {
    ScratchDir dir;
    std::filesystem::create_directories(dir.file("sub"));
    std::string main = dir.write("scene.pbrt", "WorldBegin\nInclude \"sub\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 2, 1, "directory");
}

TEST(BadInput, IncludeOfItself) {
    ScratchDir dir;
    std::string main = dir.write("scene.pbrt", "WorldBegin\nInclude \"scene.pbrt\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 2, 1, "include cycle");
}

TEST(BadInput, IncludeCycle) {
    ScratchDir dir;
    std::string a = dir.write("a.pbrt", "# a\nInclude \"b.pbrt\"\n");
    std::string b = dir.write("b.pbrt", "\n\n    Include \"a.pbrt\"\n");
    std::string main = dir.write("scene.pbrt", "WorldBegin\nInclude \"a.pbrt\"\n");
    expect_input_error([&] { parse_scene_file(main); }, b, 3, 5, "include cycle");
}

TEST(BadInput, ErrorInsideAnIncludedFile) {
    ScratchDir dir;
    std::string inc = dir.write("inc.pbrt", "Shape \"sphere\"\n Shape \"cube\"\n");
    std::string main = dir.write("scene.pbrt", "WorldBegin\nInclude \"inc.pbrt\"\n");
    expect_input_error([&] { parse_scene_file(main); }, inc, 2, 2, "unknown shape");
}

TEST(BadInput, MissingPlyFile) {
    ScratchDir dir;
    std::string main = dir.write(
        "scene.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"models/none.ply\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 2, 17, "no such file");
}

TEST(BadInput, TruncatedPly) {
    ML_NEED_SHARED("scenes/veach-bidir/models/Mesh001.ply");
    ScratchDir dir;
    std::string ply =
        test::read_file(ml::test::shared_dir() + "/scenes/veach-bidir/models/Mesh001.ply");
    dir.write("cut.ply", ply.substr(0, ply.size() - 7));
    std::string main = dir.write(
        "scene.pbrt", "WorldBegin\nShape \"plymesh\"\n  \"string filename\" \"cut.ply\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 3, 3, "truncated");
}

TEST(BadInput, MalformedPly) {
    ScratchDir dir;
    dir.write("bad.ply", "ply\nformat binary_little_endian 1.0\nelement vertex lots\nend_header\n");
    std::string main =
        dir.write("scene.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"bad.ply\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 2, 17, "malformed PLY header");
}

TEST(BadInput, MeshIndexOutOfRange) {
    expect_scene_error(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
        "  \"integer indices\" [0 1 3]\n",
        3, 3, "index 3 (entry 2) is out of range");
    expect_scene_error(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
        "  \"integer indices\" [0 -1 2]\n",
        3, 3, "out of range");
}

TEST(BadInput, IndicesNotAMultipleOfThree) {
    expect_scene_error(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
        "  \"integer indices\" [0 1 2 0]\n",
        3, 3, "not a multiple of 3");
}

TEST(BadInput, NanInTextCoordinates) {
    expect_scene_error("WorldBegin\nShape \"trianglemesh\"\n  \"point3 P\" [0 0 0 nan 0 0 0 1 0]\n",
                       3, 21, "bad number 'nan'");
}

TEST(BadInput, NanInBinaryPly) {
    ScratchDir dir;
    float nan = std::numeric_limits<float>::quiet_NaN();
    dir.write("nan.ply", test::binary_ply({{0, 0, 0}, {1, 0, 0}, {0, nan, 0}}, {{0, 1, 2}}));
    std::string main =
        dir.write("scene.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"nan.ply\"\n");
    expect_input_error([&] { parse_scene_file(main); }, main, 2, 17,
                       "vertex 2 has a non-finite coordinate");
}

TEST(BadInput, MismatchedAttributeLengths) {
    const std::string head =
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" "
        "[0 1 2]\n";
    expect_scene_error(head + "  \"normal N\" [0 0 1 0 0 1]\n", 3, 3, "2 normals");
    expect_scene_error(head + "  \"point2 uv\" [0 0 1 0 0 1 1 1]\n", 3, 3, "4 texture coordinates");
    expect_scene_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1]\n", 2, 22,
                       "multiple of 3");
}

TEST(BadInput, EmptyMesh) {
    expect_scene_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" []\n", 2, 22,
                       "must not be empty");
}

TEST(BadInput, AttributeEndWithoutBegin) {
    expect_scene_error("WorldBegin\nAttributeBegin\nAttributeEnd\n AttributeEnd\n", 4, 2,
                       "AttributeEnd without a matching AttributeBegin");
}

TEST(BadInput, AttributeBeginWithoutEnd) {
    expect_scene_error("WorldBegin\nAttributeBegin\n  AttributeBegin\n  AttributeEnd\n", 2, 1,
                       "AttributeBegin without a matching AttributeEnd");
}

TEST(BadInput, MismatchedScopeKinds) {
    expect_scene_error("WorldBegin\nAttributeBegin\nTransformEnd\n", 3, 1,
                       "TransformEnd closes the AttributeBegin");
}

TEST(BadInput, WorldDirectiveBeforeWorldBegin) {
    expect_scene_error("Shape \"sphere\"\n", 1, 1, "only allowed after WorldBegin");
    expect_scene_error("WorldBegin\nCamera \"perspective\"\n", 2, 1,
                       "not allowed after WorldBegin");
}

TEST(BadInput, UnsupportedDirectivesAndColorSpaces) {
    expect_scene_error("Option \"bool disablepixeljitter\" true\n", 1, 1, "not supported");
    expect_scene_error("ColorSpace \"aces2065-1\"\n", 1, 12, "unsupported color space");
}

TEST(BadInput, UndefinedObjectAndCoordinateSystem) {
    expect_scene_error("WorldBegin\nObjectInstance \"nope\"\n", 2, 1, "undefined object");
    expect_scene_error("CoordSysTransform \"nope\"\n", 1, 1, "unknown coordinate system");
}

TEST(BadInput, FirstBadPlyInFileOrder) {
    // PLY files load in parallel; the error reported is the first one in the file.
    ScratchDir dir;
    dir.write("bad.ply", "ply\nformat binary_little_endian 1.0\nelement vertex\nend_header\n");
    std::string main = dir.write("scene.pbrt",
                                 "WorldBegin\nShape \"plymesh\" \"string filename\" \"bad.ply\"\n"
                                 "Shape \"plymesh\" \"string filename\" \"bad.ply\"\n"
                                 "Shape \"plymesh\" \"string filename\" \"bad.ply\"\n");
    for (int i = 0; i < 5; ++i)
        expect_input_error([&] { parse_scene_file(main); }, main, 2, 17, "malformed PLY header");
}
