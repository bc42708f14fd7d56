// pbrt-v4's parameter names (tests/pbrt_v4_params.h): each is accepted where pbrt-v4 accepts it,
// or refused with a clear "not supported" at its place in the file; a name pbrt-v4 lacks stays
// an "unknown or unused" error. Also the Option directive and the spot light's old name.
#include <gtest/gtest.h>
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include <array>
#include <filesystem>
#include <set>
#include <string>

#include "film/image.h"
#include "integrators/render_job.h"
#include "parser_test_helpers.h"
#include "pbrt_v4_params.h"
#include "ply_test_helpers.h"

using namespace ml;
using ml::test::expect_scene_error;
using ml::test::kPbrtV4Params;
using ml::test::Pbrt;
using ml::test::PbrtParam;
using ml::test::ScratchDir;

namespace {

bool is_header(const std::string& d) {
    return d == "Camera" || d == "Film" || d == "Sampler" || d == "PixelFilter" ||
           d == "Integrator";
}

std::string name_of(const std::string& param) { return param.substr(param.find(' ') + 1); }

// Parameters a plugin cannot do without, left out where the row sets them itself.
std::string base_params(const PbrtParam& row, const std::string& dir) {
    const std::string d = row.directive, t = row.type, own = name_of(row.param);
    std::string out;
    auto add = [&](const std::string& name, const std::string& text) {
        if (own != name) out += " " + text;
    };
    if (d == "Shape" && t == "trianglemesh") {
        add("P", "\"point3 P\" [ 0 0 0  1 0 0  0 1 0 ]");
        add("indices", "\"integer indices\" [ 0 1 2 ]");
    } else if (d == "Shape" && t == "bilinearmesh") {
        add("P", "\"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 0 ]");
        add("indices", "\"integer indices\" [ 0 1 2 3 ]");
    } else if (d == "Shape" && t == "curve") {
        add("P", "\"point3 P\" [ 0 0 0  1 0 0  2 0 0  3 0 0 ]");
    } else if (d == "Shape" && t == "plymesh") {
        add("filename", "\"string filename\" \"" + dir + "/tri.ply\"");
    } else if ((d.rfind("Texture", 0) == 0 && t == "imagemap") ||
               (d == "LightSource" && (t == "goniometric" || t == "projection"))) {
        add("filename", "\"string filename\" \"" + dir + "/tex.exr\"");
    } else if (d == "MakeNamedMedium" && t == "uniformgrid") {
        add("density", "\"float density\" [ 1 0.5 ]");
        add("nx", "\"integer nx\" [ 2 ]");
    } else if (d == "MakeNamedMedium" && t == "rgbgrid") {
        add("sigma_a", "\"rgb sigma_a\" [ 0.1 0.2 0.3  0.3 0.2 0.1 ]");
        add("nx", "\"integer nx\" [ 2 ]");
    } else if (d == "MakeNamedMedium" && t == "nanovdb") {
        add("filename", "\"string filename\" \"" + dir + "/smoke.nvdb\"");
    } else if (d == "Material" && t == "subsurface" && (own == "sigma_a" || own == "sigma_s")) {
        add("sigma_a", "\"rgb sigma_a\" [ 0.1 0.2 0.3 ]");
        add("sigma_s", "\"rgb sigma_s\" [ 1 2 3 ]");
    } else if (d == "Material" && t == "measured") {
        add("filename", "\"string filename\" \"" + dir + "/brdf.bsdf\"");
    } else if (d == "Material" && t == "mix") {
        add("materials", "\"string materials\" [ \"ma\" \"mb\" ]");
    } else if (d == "Shape" && t == "loopsubdiv") {
        add("P", "\"point3 P\" [ 1 1 1  1 -1 -1  -1 1 -1  -1 -1 1 ]");
        add("indices", "\"integer indices\" [ 0 1 2  0 3 1  0 2 3  1 3 2 ]");
    } else if (d == "Camera" && t == "realistic") {
        add("lensfile", "\"string lensfile\" \"" + dir + "/lens.dat\"");
    } else if (d == "Film") {
        add("xresolution", "\"integer xresolution\" [ 2 ]");
        add("yresolution", "\"integer yresolution\" [ 2 ]");
    }
    return out;
}

// A scene that holds the row's directive with its parameter (and `extra`, a further parameter).
std::string scene_for(const PbrtParam& row, const std::string& dir, const std::string& extra) {
    std::string value = row.value;
    if (size_t at = value.find("$DIR"); at != std::string::npos) value.replace(at, 4, dir);
    std::string params = base_params(row, dir);
    if (*row.param) params += " \"" + std::string(row.param) + "\" " + value;
    params += extra;
    const std::string d = row.directive;
    std::string line;
    if (d == "Texture float" || d == "Texture spectrum")
        line = "Texture \"t\" \"" + d.substr(8) + "\" \"" + row.type + "\"" + params;
    else if (d == "AreaLightSource")
        line = "AttributeBegin\nAreaLightSource \"" + std::string(row.type) + "\"" + params +
               "\nShape \"sphere\"\nAttributeEnd";
    else if (d == "MakeNamedMedium")
        line = "MakeNamedMedium \"m\" \"string type\" \"" + std::string(row.type) + "\"" + params;
    else
        line = d + " \"" + row.type + "\"" + params;
    std::string text = "LookAt 0 0 5  0 0 0  0 1 0\n";
    auto header = [&](const std::string& directive, const std::string& def) {
        text += (d == directive ? line : def) + "\n";
    };
    header("Camera", "Camera \"perspective\"");
    header("Film", "Film \"rgb\" \"integer xresolution\" [ 2 ] \"integer yresolution\" [ 2 ]");
    header("Sampler", "Sampler \"independent\"");
    header("PixelFilter", "PixelFilter \"box\"");
    header("Integrator", "Integrator \"path\" \"integer maxdepth\" [ 1 ]");
    text += "WorldBegin\n";
    text += "Texture \"ftex\" \"float\" \"constant\" \"float value\" [ 0.5 ]\n";
    text += "Texture \"stex\" \"spectrum\" \"constant\" \"rgb value\" [ 0.5 0.5 0.5 ]\n";
    text += "MakeNamedMaterial \"ma\" \"string type\" \"diffuse\"\n";
    text += "MakeNamedMaterial \"mb\" \"string type\" \"conductor\"\n";
    text += "LightSource \"point\" \"point3 from\" [ 0 0 3 ]\n";
    if (!is_header(d)) text += line + "\n";
    text += "Shape \"sphere\" \"float radius\" [ 0.5 ]\n";
    return text;
}

// Parses the scene, and renders it (2 x 2 pixels, one sample) where the row is read at render
// time (the header directives); throws what either throws.
void load(const PbrtParam& row, const std::string& text, const std::string& dir) {
    SceneDesc desc = parse_scene_string(text, dir, "test.pbrt");
    if (!is_header(row.directive)) return;
    RenderOptions opt;
    opt.spp = 1;
    opt.threads = 1;
    if (std::string(row.type) == "mlt") {  // pbrt-v4's mlt is our pssmlt
        opt.set["pssmlt.bootstrap"] = "16";
        opt.set["pssmlt.chains"] = "2";
    }
    render_scene(std::move(desc), opt);
}

class PbrtParams : public ::testing::Test {
protected:
    void SetUp() override {
        Image env(8, 4), tex(4, 4);
        for (RGB& p : env.pixels) p = RGB(0.5f);
        for (RGB& p : tex.pixels) p = RGB(0.25f);
        write_image(m_dir.file("env.exr"), env);
        write_image(m_dir.file("tex.exr"), tex);
        std::filesystem::copy_file(MANYLIGHT_SOURCE_DIR "/tests/scenes/dgauss_50mm.dat",
                                   m_dir.file("lens.dat"));
        std::filesystem::copy_file(MANYLIGHT_SOURCE_DIR "/tests/scenes/mat_measured.bsdf",
                                   m_dir.file("brdf.bsdf"));
        m_dir.write("tri.ply",
                    ml::test::binary_ply({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}));
        // A NanoVDB fog volume of 4^3 voxels of density 1.
        nanovdb::GridBuilder<float> builder(0.f, nanovdb::GridClass::FogVolume);
        builder([](const nanovdb::Coord&) { return 1.f; },
                nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(3)));
        nanovdb::io::writeGrid(m_dir.file("smoke.nvdb"),
                               builder.getHandle<>(0.25, nanovdb::Vec3d(-0.5), "density"));
    }
    ScratchDir m_dir;
};

std::string describe(const PbrtParam& row) {
    return std::string(row.directive) + " \"" + row.type + "\" \"" + row.param + "\"";
}

bool refusal(const std::string& message) {
    for (const char* clear : {"not supported", "unsupported", "needs spectral"})
        if (message.find(clear) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_F(PbrtParams, EveryPbrtV4NameIsAcceptedOrClearlyRefused) {
    std::vector<std::string> gaps;
    for (const PbrtParam& row : kPbrtV4Params) {
        const std::string text = scene_for(row, m_dir.path(), "");
        SCOPED_TRACE(describe(row) + "\n" + text);
        try {
            load(row, text, m_dir.path());
            EXPECT_EQ(row.status, Pbrt::Accepted) << "accepted, but the table says otherwise";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_EQ(e.loc().file, "test.pbrt") << e.formatted();
            EXPECT_GT(e.loc().line, 0) << e.formatted();
            if (row.status == Pbrt::Refused) {
                EXPECT_TRUE(refusal(msg)) << "not a clear refusal: " << e.formatted();
                EXPECT_EQ(msg.find("unknown or unused"), std::string::npos) << e.formatted();
            } else if (row.status == Pbrt::Gap) {
                EXPECT_NE(msg.find("unknown or unused"), std::string::npos) << e.formatted();
                gaps.push_back(describe(row));
            } else {
                ADD_FAILURE() << "refused: " << e.formatted();
            }
        }
    }
    if (!gaps.empty()) {
        std::string list;
        for (const std::string& g : gaps) list += "\n  " + g;
        std::printf("pbrt-v4 names still reported as unknown (gaps):%s\n", list.c_str());
    }
}

TEST_F(PbrtParams, NamesPbrtV4LacksStayErrors) {
    // One made-up name per accepted plugin: an error at its own line, as before.
    std::set<std::string> seen;
    for (const PbrtParam& row : kPbrtV4Params) {
        if (row.status != Pbrt::Accepted || !*row.param) continue;
        if (!seen.insert(std::string(row.directive) + "/" + row.type).second) continue;
        const std::string text = scene_for(row, m_dir.path(), "\n  \"float notapbrtv4name\" [ 1 ]");
        SCOPED_TRACE(describe(row) + "\n" + text);
        try {
            load(row, text, m_dir.path());
            ADD_FAILURE() << "a name pbrt-v4 lacks was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("\"float notapbrtv4name\" is unknown or unused"),
                      std::string::npos)
                << e.formatted();
            EXPECT_EQ(e.loc().file, "test.pbrt");
            EXPECT_GT(e.loc().line, 1);
        }
    }
    EXPECT_GE(seen.size(), 30u);
}

TEST(PbrtParamsSpot, OldConeDeltaNameIsAnErrorWithAHint) {
    expect_scene_error("WorldBegin\nLightSource \"spot\"\n  \"float conedelta\" [ 10 ]\n", 3, 3,
                       "the falloff angle is \"float conedeltaangle\"");
    expect_scene_error(
        "WorldBegin\nLightSource \"spot\" \"float coneangle\" [ 20 ]\n"
        "  \"float conedeltaangle\" [ 30 ]\n",
        3, 3, "\"conedeltaangle\" must be in [0, coneangle]");
}

TEST(PbrtOption, ImageNeutralOptionsAreAccepted) {
    for (const char* option :
         {"Option \"wavefront\" true", "Option \"bool pixelstats\" false",
          "Option \"disablewavelengthjitter\" true", "Option \"disabletexturefiltering\" true",
          "Option \"msereferenceimage\" \"ref.exr\"", "Option \"rendercoordsys\" \"world\"",
          "Option \"displacementedgescale\" 2", "Option \"seed\" 7",
          "Option \"disablepixeljitter\" false", "Option \"force-diffuse\" false"}) {
        SCOPED_TRACE(option);
        EXPECT_NO_THROW(parse_scene_string(std::string(option) + "\nWorldBegin\n", "."));
    }
}

TEST(PbrtOption, OthersAreRefusedAtTheirLine) {
    expect_scene_error("Film \"rgb\"\nOption \"disablepixeljitter\" true\n", 2, 1,
                       "changes the image and is not supported");
    expect_scene_error("Option \"forcediffuse\" true\n", 1, 1, "not supported");
    expect_scene_error("\nOption \"nosuchoption\" true\n", 2, 1, "unknown Option \"nosuchoption\"");
    expect_scene_error("Option \"wavefront\" yes\n", 1, 1, "expected true or false");
    expect_scene_error("Option \"seed\" 1.5\n", 1, 1, "expected an integer");
    expect_scene_error("Option \"rendercoordsys\" \"screen\"\n", 1, 1,
                       "unknown rendering coordinate system");
    expect_scene_error("Option \"wavefront\"\n", 2, 1, "Option expects a value");
}

TEST(PbrtMlt, RendersAsPssmltWithPbrtV4sNames) {
    // pbrt-v4's "mlt" is Kelemen's MLT over BDPT's paths, our pssmlt: its names set pssmlt's
    // settings, and its "mutationsperpixel" (not the sampler's 64) the samples per pixel.
    const std::string text = R"(LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
Sampler "independent" "integer pixelsamples" [ 64 ]
Integrator "mlt" "integer mutationsperpixel" [ 4 ] "float largestepprobability" [ 0.5 ]
  "integer bootstrapsamples" [ 1000 ] "integer chains" [ 8 ] "float sigma" [ 0.02 ]
  "bool regularize" false
WorldBegin
LightSource "point" "point3 from" [ 0 0 3 ]
Shape "sphere" "float radius" [ 0.5 ]
)";
    RenderOptions opt;
    opt.threads = 1;
    RenderOutput out = render_scene(parse_scene_string(text, ".", "mlt.pbrt"), opt);
    EXPECT_EQ(out.figures.integrator, "pssmlt");
    EXPECT_EQ(out.figures.spp, 4);
    const auto& s = out.figures.integrator_stats["pssmlt"];
    EXPECT_EQ(s["bootstrap"], 1000);
    EXPECT_EQ(s["chains"], 8);
    EXPECT_FLOAT_EQ(s["large_step_prob"].get<float>(), 0.5f);
    EXPECT_FLOAT_EQ(s["sigma"].get<float>(), 0.02f);
    // --spp still decides, and a count that is not positive is an error at its line.
    opt.spp = 2;
    EXPECT_EQ(render_scene(parse_scene_string(text, ".", "mlt.pbrt"), opt).figures.spp, 2);
    std::string bad = text;
    bad.replace(bad.find("[ 4 ]"), 5, "[ 0 ]");
    opt.spp.reset();
    try {
        render_scene(parse_scene_string(bad, ".", "mlt.pbrt"), opt);
        ADD_FAILURE() << "mutationsperpixel 0 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(e.formatted().find("mlt.pbrt:5"), std::string::npos) << e.formatted();
    }
}
