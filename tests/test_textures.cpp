// Texture and material factory tests: image lookups (bilinear, point, wrap modes, v flip,
// colour decoding), the image cache, and bad input.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/scratch.h"
#include "materials/create.h"
#include "materials/textures.h"

using namespace ml;

namespace {

Param make_param(const std::string& type, const std::string& name, std::vector<double> numbers,
                 std::vector<std::string> strings = {}, std::vector<bool> bools = {}) {
    Param p;
    p.type = type;
    p.name = name;
    p.loc = FileLoc{"test.pbrt", 7, int(name.size())};
    p.numbers = std::move(numbers);
    p.strings = std::move(strings);
    p.bools = std::move(bools);
    return p;
}
Param str(const std::string& name, const std::string& v) {
    return make_param("string", name, {}, {v});
}
Param flt(const std::string& name, double v) { return make_param("float", name, {v}); }
Param tex(const std::string& name, const std::string& v) {
    return make_param("texture", name, {}, {v});
}
Param rgb(const std::string& name, RGB c) { return make_param("rgb", name, {c.r, c.g, c.b}); }

ParameterList plist(std::vector<Param> ps) {
    ParameterList l(FileLoc{"test.pbrt", 7, 1});
    for (auto& p : ps) l.add(std::move(p));
    return l;
}

class TextureTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = std::filesystem::temp_directory_path() /
                ("manylight_tex_" + std::to_string(::getpid()));
        std::filesystem::create_directories(m_dir);
        // 2 x 2 linear image, top row first: [A B; C D].
        Image img(2, 2);
        img.at(0, 0) = RGB(1, 0, 0);  // A: top left
        img.at(1, 0) = RGB(0, 1, 0);  // B: top right
        img.at(0, 1) = RGB(0, 0, 1);  // C: bottom left
        img.at(1, 1) = RGB(1, 1, 1);  // D: bottom right
        write_image((m_dir / "quad.pfm").string(), img);
        Image grey(1, 1);
        grey.at(0, 0) = RGB(0.5f);
        write_image((m_dir / "grey.png").string(), grey);  // stored sRGB-encoded, 8-bit
        Image ramp(16, 1);
        for (int x = 0; x < 16; ++x) ramp.at(x, 0) = RGB(x / 15.f);
        write_image((m_dir / "ramp.pfm").string(), ramp);
    }
    void TearDown() override { std::filesystem::remove_all(m_dir); }

    std::shared_ptr<RGBTexture> image_tex(std::vector<Param> extra) {
        extra.push_back(str("filename", "quad.pfm"));
        ParameterList l = plist(std::move(extra));
        create_texture("t", "spectrum", "imagemap", l, m_dir.string(), m_textures, m_cache, {});
        l.check_unused();
        return m_textures.rgbs.at("t");
    }
    static RGB at(const RGBTexture& t, float u, float v) { return t.eval({Vec3(), Vec2(u, v)}); }

    std::filesystem::path m_dir;
    NamedTextures m_textures;
    ImageCache m_cache;
};

void expect_rgb(const RGB& got, const RGB& want, float tol = 1e-5f) {
    EXPECT_NEAR(got.r, want.r, tol);
    EXPECT_NEAR(got.g, want.g, tol);
    EXPECT_NEAR(got.b, want.b, tol);
}

}  // namespace

TEST_F(TextureTest, BilinearAtTexelCentresAndBetween) {
    auto t = image_tex({});
    // v is flipped: v = 0.75 is the top row.
    expect_rgb(at(*t, 0.25f, 0.75f), RGB(1, 0, 0));
    expect_rgb(at(*t, 0.75f, 0.75f), RGB(0, 1, 0));
    expect_rgb(at(*t, 0.25f, 0.25f), RGB(0, 0, 1));
    expect_rgb(at(*t, 0.75f, 0.25f), RGB(1, 1, 1));
    // Halfway between A and B, then the centre of all four.
    expect_rgb(at(*t, 0.5f, 0.75f), RGB(0.5f, 0.5f, 0));
    expect_rgb(at(*t, 0.5f, 0.5f), RGB(0.5f, 0.5f, 0.5f));
}

TEST_F(TextureTest, WrapModes) {
    auto rep = image_tex({str("wrap", "repeat")});
    expect_rgb(at(*rep, 1.25f, 0.75f), RGB(1, 0, 0));
    expect_rgb(at(*rep, -0.75f, -0.25f), RGB(1, 0, 0));
    // At u = 0 bilinear repeat blends the left and right columns.
    expect_rgb(at(*rep, 0.f, 0.75f), RGB(0.5f, 0.5f, 0));
    auto clamp = image_tex({str("wrap", "clamp")});
    expect_rgb(at(*clamp, 0.f, 0.75f), RGB(1, 0, 0));
    expect_rgb(at(*clamp, 3.f, 0.75f), RGB(0, 1, 0));
    auto black = image_tex({str("wrap", "black"), str("filter", "point")});
    expect_rgb(at(*black, 1.25f, 0.75f), RGB(0));
    expect_rgb(at(*black, 0.25f, 0.75f), RGB(1, 0, 0));
    auto black_bilerp = image_tex({str("wrap", "black")});
    expect_rgb(at(*black_bilerp, 0.f, 0.75f), RGB(0.5f, 0, 0));
}

TEST_F(TextureTest, PointFilterMappingScaleInvert) {
    auto p = image_tex({str("filter", "point")});
    expect_rgb(at(*p, 0.49f, 0.99f), RGB(1, 0, 0));
    expect_rgb(at(*p, 0.51f, 0.01f), RGB(1, 1, 1));
    // st = (2u + 0.5, v): u = 0 lands on the right column's centre... of the repeat.
    auto m = image_tex({flt("uscale", 2), flt("udelta", 0.25f), str("filter", "point")});
    expect_rgb(at(*m, 0.25f, 0.75f), RGB(0, 1, 0));  // st.x = 0.75
    auto s = image_tex({flt("scale", 2), make_param("bool", "invert", {}, {}, {true})});
    expect_rgb(at(*s, 0.25f, 0.75f), RGB(0, 1, 1));  // 1 - 2 * (1, 0, 0), clamped at zero
}

TEST_F(TextureTest, FloatImageReadsFirstChannel) {
    ParameterList l = plist({str("filename", "quad.pfm"), str("filter", "point")});
    create_texture("f", "float", "imagemap", l, m_dir.string(), m_textures, m_cache, {});
    auto& t = *m_textures.floats.at("f");
    EXPECT_FLOAT_EQ(t.eval({Vec3(), Vec2(0.25f, 0.75f)}), 1.f);
    EXPECT_FLOAT_EQ(t.eval({Vec3(), Vec2(0.75f, 0.75f)}), 0.f);
}

TEST_F(TextureTest, SrgbDecodedByDefaultForPng) {
    auto make = [&](const std::string& name, std::vector<Param> extra) {
        extra.push_back(str("filename", (m_dir / "grey.png").string()));  // absolute path
        ParameterList l = plist(std::move(extra));
        create_texture(name, "spectrum", "imagemap", l, "/nonexistent", m_textures, m_cache, {});
        return m_textures.rgbs.at(name)->eval({Vec3(), Vec2(0.5f, 0.5f)}).g;
    };
    float stored = std::round(linear_to_srgb(0.5f) * 255) / 255;
    EXPECT_NEAR(make("a", {}), srgb_to_linear(stored), 1e-5f);
    EXPECT_NEAR(make("b", {str("encoding", "sRGB")}), srgb_to_linear(stored), 1e-5f);
    EXPECT_NEAR(make("c", {str("encoding", "linear")}), stored, 1e-5f);
    EXPECT_NEAR(make("d", {str("encoding", "gamma 2.2")}), std::pow(stored, 2.2f), 1e-4f);
    // Float files are linear whatever the encoding says.
    ParameterList l = plist({str("filename", "quad.pfm"), str("encoding", "sRGB")});
    create_texture("e", "spectrum", "imagemap", l, m_dir.string(), m_textures, m_cache, {});
    expect_rgb(at(*m_textures.rgbs.at("e"), 0.5f, 0.5f), RGB(0.5f));
}

TEST_F(TextureTest, ImagesLoadedOncePerPath) {
    image_tex({});
    image_tex({str("wrap", "clamp")});
    ParameterList l = plist({str("filename", "quad.pfm")});
    create_texture("f", "float", "imagemap", l, m_dir.string(), m_textures, m_cache, {});
    EXPECT_EQ(m_cache.images.size(), 1u);
}

TEST_F(TextureTest, ConstantAndScale) {
    ParameterList c = plist({rgb("value", RGB(0.2f, 0.4f, 0.6f))});
    create_texture("c", "spectrum", "constant", c, "", m_textures, m_cache, {});
    ParameterList f = plist({flt("value", 3)});
    create_texture("f", "float", "constant", f, "", m_textures, m_cache, {});
    ParameterList s = plist({tex("tex", "c"), tex("scale", "f")});
    create_texture("s", "spectrum", "scale", s, "", m_textures, m_cache, {});
    s.check_unused();
    expect_rgb(m_textures.rgbs.at("s")->eval({}), RGB(0.6f, 1.2f, 1.8f));
    ParameterList sf = plist({tex("tex", "f"), flt("scale", 0.5f)});
    create_texture("sf", "float", "scale", sf, "", m_textures, m_cache, {});
    EXPECT_FLOAT_EQ(m_textures.floats.at("sf")->eval({}), 1.5f);
}

TEST_F(TextureTest, BadInputThrowsAtItsLocation) {
    auto make = [&](const std::string& cls, std::vector<Param> ps) {
        ParameterList l = plist(std::move(ps));
        create_texture("x", "spectrum", cls, l, m_dir.string(), m_textures, m_cache,
                       FileLoc{"scene.pbrt", 3, 1});
    };
    EXPECT_THROW(make("imagemap", {str("filename", "missing.png")}), InputError);
    EXPECT_THROW(make("ptex", {}), InputError);
    EXPECT_THROW(make("imagemap", {str("filename", "quad.pfm"), str("wrap", "mirror")}),
                 InputError);
    EXPECT_THROW(make("imagemap", {str("filename", "quad.pfm"), str("filter", "cubic")}),
                 InputError);
    EXPECT_THROW(make("imagemap", {str("filename", "quad.pfm"), str("encoding", "gamma x")}),
                 InputError);
    EXPECT_THROW(make("scale", {tex("tex", "nope")}), InputError);
    ParameterList l = plist({});
    EXPECT_THROW(create_texture("x", "color", "constant", l, "", m_textures, m_cache, {}),
                 InputError);
    try {
        make("imagemap", {str("filename", "quad.pfm"), str("wrap", "mirror")});
    } catch (const InputError& e) {
        EXPECT_EQ(e.loc().file, "test.pbrt");  // the parameter's own location
    }
}

// ---- materials ----

namespace {

SurfaceInteraction flat_hit() {
    SurfaceInteraction si;
    si.p = Vec3(0, 0, 0);
    si.ng = si.ns = Vec3(0, 0, 1);
    si.dpdu = Vec3(1, 0, 0);
    si.dpdv = Vec3(0, 1, 0);
    si.uv = Vec2(0.5f, 0.5f);
    si.wo = normalize(Vec3(0.2f, 0.1f, 1));
    return si;
}

}  // namespace

TEST_F(TextureTest, MaterialsBuildWithDefaultsAndUseAllTheirParameters) {
    ScratchBuffer scratch;
    SurfaceInteraction si = flat_hit();
    struct Case {
        std::string type;
        std::vector<Param> params;
        uint8_t flags;
    };
    std::vector<Case> cases = {
        {"diffuse", {}, kBxdfDiffuseReflection},
        {"diffuse", {rgb("reflectance", RGB(0.1f, 0.2f, 0.3f))}, kBxdfDiffuseReflection},
        {"conductor", {}, kBxdfSpecularReflection},
        {"conductor",
         {make_param("spectrum", "eta", {}, {"metal-Ag-eta"}),
          make_param("spectrum", "k", {}, {"metal-Ag-k"}), flt("uroughness", 0.1f),
          flt("vroughness", 0.3f), make_param("bool", "remaproughness", {}, {}, {false})},
         kBxdfGlossyReflection},
        {"conductor",
         {rgb("reflectance", RGB(0.9f)), flt("roughness", 0.2f)},
         kBxdfGlossyReflection},
        {"dielectric", {}, kBxdfSpecularReflection | kBxdfSpecularTransmission},
        {"dielectric",
         {make_param("spectrum", "eta", {}, {"glass-BK7"}), flt("roughness", 0.1f)},
         kBxdfGlossyReflection | kBxdfGlossyTransmission},
        {"coateddiffuse", {}, kBxdfSpecularReflection | kBxdfDiffuse},
        {"coateddiffuse",
         {rgb("reflectance", RGB(0.3f)), flt("roughness", 0.1f), flt("thickness", 0.1f),
          flt("eta", 1.33f), rgb("albedo", RGB(0)), flt("g", 0.2f),
          make_param("integer", "maxdepth", {5}), make_param("integer", "nsamples", {2})},
         kBxdfGlossyReflection | kBxdfDiffuse},
        {"diffusetransmission",
         {flt("scale", 2)},
         kBxdfDiffuseReflection | kBxdfDiffuseTransmission},
    };
    for (auto& c : cases) {
        ParameterList l = plist(c.params);
        auto m = create_material(c.type, l, m_textures, {});
        EXPECT_NO_THROW(l.check_unused()) << c.type;
        EXPECT_EQ(m->type(), c.type);
        Bsdf b = m->get_bsdf(si, scratch);
        ASSERT_TRUE(b);
        EXPECT_EQ(b.flags(), c.flags) << c.type;
        auto s = b.sample(si.wo, 0.3f, Vec2(0.4f, 0.6f));
        EXPECT_TRUE(s.has_value()) << c.type;
    }
    // Diffuse transmission's scale multiplies both lobes (0.25 * 2).
    ParameterList l = plist({flt("scale", 2)});
    Bsdf b = create_material("diffusetransmission", l, m_textures, {})->get_bsdf(si, scratch);
    EXPECT_NEAR(b.eval(si.wo, Vec3(0, 0, -1)).g, 0.5f * kInvPi, 1e-6f);
}

TEST_F(TextureTest, MaterialTexturesAndErrors) {
    image_tex({});  // "t": the quad
    ScratchBuffer scratch;
    SurfaceInteraction si = flat_hit();
    si.uv = Vec2(0.25f, 0.75f);  // red texel
    ParameterList l = plist({tex("reflectance", "t")});
    Bsdf b = create_material("diffuse", l, m_textures, {})->get_bsdf(si, scratch);
    expect_rgb(b.eval(si.wo, Vec3(0, 0, 1)), RGB(kInvPi, 0, 0));

    auto bad = [&](const std::string& type, std::vector<Param> ps) {
        ParameterList pl = plist(std::move(ps));
        create_material(type, pl, m_textures, FileLoc{"scene.pbrt", 9, 1});
    };
    EXPECT_THROW(bad("measured", {}), InputError);  // no filename
    EXPECT_THROW(bad("plastic", {}), InputError);
    EXPECT_THROW(bad("diffuse", {tex("reflectance", "undefined")}), InputError);
    EXPECT_THROW(bad("diffuse", {str("normalmap", "n.png")}), InputError);
    EXPECT_THROW(bad("coateddiffuse", {rgb("albedo", RGB(0.5f))}), InputError);
    EXPECT_THROW(bad("conductor", {rgb("reflectance", RGB(0.5f)), rgb("eta", RGB(1))}), InputError);
    try {
        bad("diffuse", {tex("reflectance", "undefined")});
    } catch (const InputError& e) {
        EXPECT_EQ(e.loc().file, "test.pbrt");
        EXPECT_NE(std::string(e.what()).find("undefined"), std::string::npos);
    }
    try {
        bad("measured", {});
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("\"string filename\" (a .bsdf file) is required"),
                  std::string::npos);
    }
    try {
        bad("plastic", {});
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown material type"), std::string::npos);
    }
}

TEST_F(TextureTest, BumpMappingTiltsTheShadingNormal) {
    ParameterList r =
        plist({str("filename", "ramp.pfm"), str("wrap", "clamp"), flt("scale", 0.1f)});
    create_texture("bump", "float", "imagemap", r, m_dir.string(), m_textures, m_cache, {});
    ScratchBuffer scratch;
    SurfaceInteraction si = flat_hit();
    ParameterList l = plist({tex("displacement", "bump")});
    auto m = create_material("diffuse", l, m_textures, {});
    Bsdf b = m->get_bsdf(si, scratch);
    // Height grows with u (0.1 over the unit square): the normal leans towards -u.
    Vec3 n = b.frame().n;
    EXPECT_LT(n.x, -0.05f);
    EXPECT_NEAR(n.y, 0.f, 1e-4f);
    EXPECT_GT(dot(n, si.ng), 0.f);
    EXPECT_NEAR(n.x / n.z, -0.1f, 0.02f);
    // Flipped tangents (a mirrored uv layout) must not flip the normal below the surface.
    si.dpdv = Vec3(0, -1, 0);
    EXPECT_GT(dot(m->get_bsdf(si, scratch).frame().n, si.ng), 0.f);
    // Without displacement the frame follows ns and dpdu.
    ParameterList plain = plist({});
    Frame f =
        create_material("diffuse", plain, m_textures, {})->get_bsdf(flat_hit(), scratch).frame();
    EXPECT_NEAR(f.n.z, 1.f, 1e-6f);
    EXPECT_NEAR(f.s.x, 1.f, 1e-6f);
}

TEST_F(TextureTest, ANormalMapSetsTheShadingNormalInTheTangentFrame) {
    // One texel of (n + 1) / 2 with n = (0.6, 0, 0.8) in tangent space (x along dpdu, z the
    // normal): the frame's normal is that direction in world space, turned to follow dpdu's
    // direction and the geometric normal's side; the texel's other encodings follow suit.
    auto frame_for = [&](const Vec3& n_tangent, const SurfaceInteraction& si) {
        Image img(1, 1);
        img.at(0, 0) = RGB((n_tangent.x + 1) / 2, (n_tangent.y + 1) / 2, (n_tangent.z + 1) / 2);
        write_image((m_dir / "n.pfm").string(), img);
        m_cache.images.clear();
        ParameterList l = plist({str("normalmap", "n.pfm")});
        ScratchBuffer scratch;
        return create_material("diffuse", l, m_textures, {}, {}, &m_cache, m_dir.string())
            ->get_bsdf(si, scratch)
            .frame();
    };
    SurfaceInteraction si = flat_hit();
    Frame f = frame_for(Vec3(0.6f, 0, 0.8f), si);
    EXPECT_NEAR(f.n.x, 0.6f, 1e-3f);
    EXPECT_NEAR(f.n.y, 0, 1e-3f);
    EXPECT_NEAR(f.n.z, 0.8f, 1e-3f);
    // dpdu along +y: the tangent's x is world y.
    si.dpdu = Vec3(0, 1, 0);
    si.dpdv = Vec3(-1, 0, 0);
    f = frame_for(Vec3(0.6f, 0, 0.8f), si);
    EXPECT_NEAR(f.n.x, 0, 1e-3f);
    EXPECT_NEAR(f.n.y, 0.6f, 1e-3f);
    // The map's y is the bitangent n x dpdu.
    f = frame_for(Vec3(0, 0.6f, 0.8f), flat_hit());
    EXPECT_NEAR(f.n.y, 0.6f, 1e-3f);
    EXPECT_NEAR(f.n.z, 0.8f, 1e-3f);
    // A normal below the surface is turned to the geometric normal's side.
    EXPECT_GT(frame_for(Vec3(0.6f, 0, -0.8f), flat_hit()).n.z, 0);
    // No shading normal of its own: refused.
    ParameterList mix = plist({str("normalmap", "n.pfm")});
    EXPECT_THROW(create_material("interface", mix, m_textures, {}, {}, &m_cache, m_dir.string()),
                 InputError);
    ParameterList missing = plist({str("normalmap", "none.png")});
    EXPECT_THROW(create_material("diffuse", missing, m_textures, {}, {}, &m_cache, m_dir.string()),
                 InputError);
}
