// The `Material` directive's factory: pbrt-v4's parameter names and defaults for diffuse,
// conductor, dielectric, thindielectric, coateddiffuse, coatedconductor, diffusetransmission,
// mix, interface, hair, subsurface and measured.
#include "materials/create.h"

#include <cmath>

#include "core/scattering_presets.h"
#include "materials/beam_diffusion.h"
#include "materials/hair.h"
#include "materials/materials.h"
#include "materials/measured.h"
#include "materials/textures.h"

namespace ml {

namespace {

class MaterialParams {
public:
    MaterialParams(const ParameterList& params, const NamedTextures& textures)
        : m_params(params), m_textures(textures) {}

    bool has(const std::string& name) const { return m_params.has(name); }

    // A float value, or a float texture by name.
    FloatParam get_float(const std::string& name, float def) const {
        const Param* p = m_params.find(name);
        FloatParam out{def, nullptr};
        if (!p) return out;
        if (p->type == "texture") {
            std::string tname = m_params.get_texture(name);
            auto it = m_textures.floats.find(tname);
            if (it == m_textures.floats.end())
                throw_input_error(p->loc, "undefined float texture \"{}\"", tname);
            out.tex = it->second;
            if (auto* c = dynamic_cast<const ConstantFloatTexture*>(out.tex.get())) {
                out.value = c->value();
                out.tex = nullptr;
            }
            return out;
        }
        out.value = m_params.get_float(name, def);
        return out;
    }

    // A colour (rgb, spectrum, blackbody, or a single float), or a spectrum texture by name (a
    // float texture is accepted as grey).
    RGBParam get_rgb(const std::string& name, RGB def) const {
        const Param* p = m_params.find(name);
        RGBParam out{def, nullptr};
        if (!p) return out;
        if (p->type == "texture") {
            std::string tname = m_params.get_texture(name);
            if (auto it = m_textures.rgbs.find(tname); it != m_textures.rgbs.end()) {
                out.tex = it->second;
            } else if (auto itf = m_textures.floats.find(tname); itf != m_textures.floats.end()) {
                out.tex = std::make_shared<FloatAsRGBTexture>(itf->second);
            } else {
                throw_input_error(p->loc, "undefined spectrum texture \"{}\"", tname);
            }
            if (auto* c = dynamic_cast<const ConstantRGBTexture*>(out.tex.get())) {
                out.value = c->value();
                out.tex = nullptr;
            }
            return out;
        }
        if (p->type == "float") {
            out.value = RGB(m_params.get_float(name, 0));
            return out;
        }
        out.value = m_params.get_rgb(name).value_or(def);
        return out;
    }

    // "roughness", "uroughness", "vroughness", each name after `prefix` (coatedconductor's
    // "interface." and "conductor.").
    RoughnessParams roughness(float def, const std::string& prefix = "") const {
        RoughnessParams r;
        FloatParam both = get_float(prefix + "roughness", def);
        r.u = has(prefix + "uroughness") ? get_float(prefix + "uroughness", def) : both;
        r.v = has(prefix + "vroughness") ? get_float(prefix + "vroughness", def) : both;
        r.remap = m_params.get_bool("remaproughness", true);
        return r;
    }

    std::shared_ptr<FloatTexture> displacement() const {
        if (!has("displacement")) return nullptr;
        FloatParam d = get_float("displacement", 0);
        if (d.tex) return d.tex;
        // A constant displacement moves the surface but leaves its normal alone.
        return nullptr;
    }

    const ParameterList& list() const { return m_params; }

private:
    const ParameterList& m_params;
    const NamedTextures& m_textures;
};

const FileLoc& loc_of(const ParameterList& params, const std::string& name, const FileLoc& def) {
    for (const Param& p : params.params())
        if (p.name == name) return p.loc;
    return def;
}

RGB named_or_die(const char* name) { return named_spectrum_rgb(name).value_or(RGB(1)); }

// pbrt-v4's "subsurface": a dielectric boundary ("eta" 1.33, its roughness) over a homogeneous
// medium given by a measured medium's "name", by "sigma_a" and "sigma_s", or pbrt-v4's default
// (skim milk's coefficients, mm^-1), times "scale". pbrt-v4 shades it with a tabulated BSSRDF;
// manylight walks the medium itself (the shape's inside, see SceneBuilder).
std::unique_ptr<Material> create_subsurface(const ParameterList& params, const MaterialParams& mp,
                                            std::shared_ptr<FloatTexture> displacement,
                                            const FileLoc& loc) {
    InteriorMedium m;
    m.g = params.get_float("g", 0);
    if (!(m.g > -1 && m.g < 1))
        throw_input_error(loc_of(params, "g", loc), "subsurface: \"g\" must be in (-1, 1)");
    auto constant = [&](const char* name) {
        const RGBParam c = mp.get_rgb(name, RGB(0));
        if (c.tex)
            throw_input_error(loc_of(params, name, loc),
                              "subsurface: a textured \"{}\" is not supported (the medium inside "
                              "is homogeneous): give a constant",
                              name);
        return c.value;
    };
    // The four ways pbrt-v4 gives the medium, one at a time (it leaves the others unused, which
    // is an error): a measured medium's "name", "sigma_a" and "sigma_s", "reflectance" (with
    // "mfp"), or none (skim milk).
    const bool by_reflectance = params.has("reflectance");
    if (params.has("mfp") && !by_reflectance)
        throw_input_error(loc_of(params, "mfp", loc),
                          "subsurface: \"mfp\" goes with \"reflectance\"");
    if (by_reflectance && (params.has("name") || params.has("sigma_a") || params.has("sigma_s")))
        throw_input_error(loc_of(params, "reflectance", loc),
                          "subsurface: \"reflectance\" gives sigma_a and sigma_s; leave out "
                          "\"name\", \"sigma_a\" and \"sigma_s\"");
    const FloatParam eta = mp.get_float("eta", 1.33f);
    if (eta.tex)
        throw_input_error(loc_of(params, "eta", loc),
                          "subsurface: a textured \"eta\" is not supported");
    const float scale = params.get_float("scale", 1);
    if (!(scale >= 0) || !std::isfinite(scale))
        throw_input_error(loc_of(params, "scale", loc), "subsurface: \"scale\" must be >= 0");
    if (by_reflectance) {
        // pbrt-v4's inversion through photon beam diffusion (materials/beam_diffusion.h);
        // "scale" multiplies the mean free path.
        const RGB reflectance = constant("reflectance");
        const RGB mfp = (params.has("mfp") ? constant("mfp") : RGB(1)) * scale;
        if (!(mfp.r > 0 && mfp.g > 0 && mfp.b > 0) || !mfp.is_finite())
            throw_input_error(loc_of(params, params.has("mfp") ? "mfp" : "scale", loc),
                              "subsurface: the mean free path (\"mfp\" times \"scale\") must be "
                              "positive and finite");
        subsurface_from_diffuse(BeamDiffusionTable(m.g, eta.value), reflectance, mfp, &m.sigma_a,
                                &m.sigma_s);
    } else if (params.has("name")) {
        const std::string name = params.get_string("name", "");
        const auto preset = scattering_preset(name);
        if (!preset)
            throw_input_error(loc_of(params, "name", loc),
                              "subsurface: unknown \"name\" \"{}\" (pbrt-v4's are {})", name,
                              scattering_preset_names());
        if (params.has("sigma_a") || params.has("sigma_s"))
            throw_input_error(loc_of(params, "name", loc),
                              "subsurface: \"name\" gives sigma_a and sigma_s; leave out "
                              "\"sigma_a\" and \"sigma_s\"");
        // pbrt-v4 ignores "g" here (the tables hold reduced scattering coefficients).
        if (params.has("g"))
            throw_input_error(loc_of(params, "g", loc),
                              "subsurface: \"g\" with a measured medium's \"name\" (pbrt-v4 "
                              "ignores it: the table's scattering is reduced, for g = 0)");
        m.sigma_a = preset->sigma_a;
        m.sigma_s = preset->sigma_s;
    } else if (params.has("sigma_a") != params.has("sigma_s")) {
        throw_input_error(loc_of(params, params.has("sigma_a") ? "sigma_a" : "sigma_s", loc),
                          "subsurface: \"sigma_a\" and \"sigma_s\" go together");
    } else if (params.has("sigma_a")) {
        m.sigma_a = constant("sigma_a");
        m.sigma_s = constant("sigma_s");
    } else {
        m.sigma_a = RGB(.0011f, .0024f, .014f);
        m.sigma_s = RGB(2.55f, 3.21f, 3.77f);
    }
    if (!by_reflectance) {
        m.sigma_a *= scale;
        m.sigma_s *= scale;
    }
    for (const RGB& c : {m.sigma_a, m.sigma_s})
        if (!(c.r >= 0 && c.g >= 0 && c.b >= 0) || !c.is_finite())
            throw_input_error(loc,
                              "subsurface: \"sigma_a\" and \"sigma_s\" must be finite and "
                              "non-negative");
    return std::make_unique<DielectricMaterial>(eta, mp.roughness(0), std::move(displacement), m);
}

// The material itself, before its normal map.
std::unique_ptr<Material> create_material_of_type(
    const std::string& type, const ParameterList& params, const NamedTextures& textures,
    const FileLoc& loc, const std::map<std::string, const Material*>& named,
    const std::string& base_dir) {
    MaterialParams mp(params, textures);
    auto displacement = mp.displacement();

    if (type == "diffuse") {
        return std::make_unique<DiffuseMaterial>(mp.get_rgb("reflectance", RGB(0.5f)),
                                                 displacement);
    }
    if (type == "diffusetransmission") {
        RGBParam r = mp.get_rgb("reflectance", RGB(0.25f));
        RGBParam t = mp.get_rgb("transmittance", RGB(0.25f));
        float scale = params.get_float("scale", 1);
        return std::make_unique<DiffuseTransmissionMaterial>(r, t, scale, displacement);
    }
    if (type == "conductor") {
        bool has_reflectance = params.has("reflectance");
        if (has_reflectance && (params.has("eta") || params.has("k")))
            throw_input_error(loc_of(params, "reflectance", loc),
                              "conductor: \"reflectance\" cannot be given with \"eta\" or \"k\"");
        RGBParam eta = mp.get_rgb("eta", named_or_die("metal-Cu-eta"));
        RGBParam k = mp.get_rgb("k", named_or_die("metal-Cu-k"));
        RGBParam reflectance = mp.get_rgb("reflectance", RGB(0));
        return std::make_unique<ConductorMaterial>(eta, k, reflectance, has_reflectance,
                                                   mp.roughness(0), displacement);
    }
    if (type == "dielectric" || type == "thindielectric" || type == "coateddiffuse") {
        // eta: a float, a float texture, or a spectrum (glasses are constant in RGB; a
        // spectrally varying one is averaged: no dispersion here).
        FloatParam eta{1.5f, nullptr};
        if (const Param* p = params.find("eta")) {
            if (p->type == "float" || p->type == "texture") {
                eta = mp.get_float("eta", 1.5f);
            } else {
                eta.value = params.get_rgb("eta").value_or(RGB(1.5f)).average();
            }
        }
        if (type == "dielectric")
            return std::make_unique<DielectricMaterial>(eta, mp.roughness(0), displacement);
        if (type == "thindielectric")
            return std::make_unique<ThinDielectricMaterial>(eta, displacement);
        RGBParam reflectance = mp.get_rgb("reflectance", RGB(0.5f));
        RoughnessParams roughness = mp.roughness(0);
        // pbrt-v4's layer thickness (absorption along each pass) and random-walk depth limit
        // change its expected value and are modelled; "nsamples" only changes its noise and
        // "g" only matters in a scattering medium. A non-zero medium albedo would need the
        // random walk, so it is refused rather than ignored.
        FloatParam thickness = mp.get_float("thickness", 0.01f);
        if (thickness.tex)
            throw_input_error(loc_of(params, "thickness", loc),
                              "coateddiffuse: a textured \"thickness\" is not supported");
        if (!std::isfinite(thickness.value) || thickness.value < 0)
            throw_input_error(loc_of(params, "thickness", loc),
                              "coateddiffuse: \"thickness\" must be non-negative");
        int maxdepth = params.get_int("maxdepth", 10);
        mp.get_float("g", 0);
        params.get_int("nsamples", 1);
        if (params.has("albedo")) {
            RGBParam albedo = mp.get_rgb("albedo", RGB(0));
            if (albedo.tex || !albedo.value.is_black())
                throw_input_error(loc_of(params, "albedo", loc),
                                  "coateddiffuse: a non-zero \"albedo\" (scattering coat) is not "
                                  "supported");
        }
        return std::make_unique<CoatedDiffuseMaterial>(reflectance, eta, roughness, thickness.value,
                                                       maxdepth, displacement);
    }
    if (type == "mix") {
        std::vector<std::string> names = params.get_strings("materials");
        const FileLoc& at = loc_of(params, "materials", loc);
        if (names.size() != 2)
            throw_input_error(at, "mix: \"string materials\" must name two materials, got {}",
                              names.size());
        const Material* m[2];
        for (int i = 0; i < 2; ++i) {
            auto it = named.find(names[size_t(i)]);
            if (it == named.end())
                throw_input_error(at, "mix: undefined named material \"{}\"", names[size_t(i)]);
            m[i] = it->second;
            if (m[i]->type() == "interface" || m[i]->interior_medium())
                throw_input_error(at, "mix: the \"{}\" material \"{}\" cannot be mixed",
                                  m[i]->type(), names[size_t(i)]);
        }
        return std::make_unique<MixMaterial>(m[0], m[1], mp.get_float("amount", 0.5f));
    }
    if (type == "interface") {
        if (displacement)
            throw_input_error(loc_of(params, "displacement", loc),
                              "interface: the material does not scatter; \"displacement\" has "
                              "nothing to bump");
        return std::make_unique<InterfaceMaterial>();
    }
    if (type == "coatedconductor") {
        CoatedConductorParams cc;
        cc.interface_roughness = mp.roughness(0, "interface.");
        cc.conductor_roughness = mp.roughness(0, "conductor.");
        if (const Param* p = params.find("interface.eta")) {
            // A float, or a spectrum averaged (no dispersion here); not a texture in pbrt-v4.
            cc.eta = p->type == "float"
                         ? params.get_float("interface.eta", 1.5f)
                         : params.get_rgb("interface.eta").value_or(RGB(1.5f)).average();
        }
        cc.thickness = mp.get_float("thickness", 0.01f);
        cc.use_reflectance = params.has("reflectance");
        if (cc.use_reflectance && (params.has("conductor.eta") || params.has("conductor.k")))
            throw_input_error(loc_of(params, "reflectance", loc),
                              "coatedconductor: \"reflectance\" cannot be given with "
                              "\"conductor.eta\" or \"conductor.k\"");
        cc.conductor_eta = mp.get_rgb("conductor.eta", named_or_die("metal-Cu-eta"));
        cc.conductor_k = mp.get_rgb("conductor.k", named_or_die("metal-Cu-k"));
        cc.reflectance = mp.get_rgb("reflectance", RGB(0));
        cc.maxdepth = params.get_int("maxdepth", 10);
        // As for coateddiffuse: "nsamples" only changes pbrt-v4's noise, "g" only matters in a
        // scattering coat, which is refused.
        mp.get_float("g", 0);
        params.get_int("nsamples", 1);
        if (params.has("albedo")) {
            RGBParam albedo = mp.get_rgb("albedo", RGB(0));
            if (albedo.tex || !albedo.value.is_black())
                throw_input_error(loc_of(params, "albedo", loc),
                                  "coatedconductor: a non-zero \"albedo\" (scattering coat) is "
                                  "not supported");
        }
        return std::make_unique<CoatedConductorMaterial>(std::move(cc), displacement);
    }
    if (type == "hair") {
        // pbrt-v4's precedence: sigma_a, else reflectance (or its older name "color"), else the
        // melanin concentrations, else eumelanin 1.3. Whatever is overridden is still read
        // (pbrt-v4 only warns about it).
        using Source = HairMaterial::Source;
        RGBParam sigma_a = mp.get_rgb("sigma_a", RGB(0));
        RGBParam reflectance = mp.get_rgb("reflectance", RGB(0));
        RGBParam color = mp.get_rgb("color", RGB(0));
        FloatParam eu = mp.get_float("eumelanin", 0), pheo = mp.get_float("pheomelanin", 0);
        Source source = Source::melanin;
        RGBParam colour;
        if (params.has("sigma_a")) {
            source = Source::sigma_a, colour = sigma_a;
        } else if (params.has("reflectance") || params.has("color")) {
            source = Source::reflectance;
            colour = params.has("reflectance") ? reflectance : color;
        } else if (!params.has("eumelanin") && !params.has("pheomelanin")) {
            eu = FloatParam{1.3f, nullptr};
        }
        return std::make_unique<HairMaterial>(
            source, colour, eu, pheo, mp.get_float("eta", 1.55f), mp.get_float("beta_m", 0.3f),
            mp.get_float("beta_n", 0.3f), mp.get_float("alpha", 2.f));
    }
    if (type == "subsurface") return create_subsurface(params, mp, displacement, loc);
    if (type == "measured") {
        const std::string filename = params.get_string("filename", "");
        if (filename.empty())
            throw_input_error(loc, "measured: \"string filename\" (a .bsdf file) is required");
        return std::make_unique<MeasuredMaterial>(
            load_measured_brdf(resolve_path(filename, base_dir), loc_of(params, "filename", loc)),
            displacement);
    }
    throw_input_error(loc, "unknown material type \"{}\"", type);
}

}  // namespace

std::unique_ptr<Material> create_material(const std::string& type, const ParameterList& params,
                                          const NamedTextures& textures, const FileLoc& loc,
                                          const std::map<std::string, const Material*>& named,
                                          ImageCache* images, const std::string& base_dir) {
    auto material = create_material_of_type(type, params, textures, loc, named, base_dir);
    if (!params.has("normalmap")) return material;
    const FileLoc& at = loc_of(params, "normalmap", loc);
    const std::string filename = params.get_string("normalmap", "");
    auto* base = dynamic_cast<MaterialBase*>(material.get());
    if (!base)
        throw_input_error(at,
                          "\"normalmap\" on a \"{}\" material, which has no shading normal "
                          "of its own",
                          type);
    if (!images) throw_input_error(at, "\"normalmap\" is not supported here");
    base->set_normal_map(
        std::make_shared<const ImageLookup>(normal_map_lookup(*images, base_dir, filename, at)));
    return material;
}

}  // namespace ml
