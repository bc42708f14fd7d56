// The LightSource / AreaLightSource factories: pbrt-v4 parameter names and defaults. RGB values
// are RGB radiometric quantities directly: pbrt-v4's photometric normalisation of RGB illuminants
// divides by the illuminant's luminance only, which cancels in an RGB renderer, so "power" and
// "illuminance" rescale the given colour exactly as pbrt-v4 does.
#include <filesystem>

#include "lights/create.h"
#include "lights/lights.h"

namespace ml {
namespace {

const FileLoc& loc_of(const ParameterList& params, const std::string& name, const FileLoc& def) {
    const Param* p = params.find(name);
    return p ? p->loc : def;
}

RGB get_color(const ParameterList& params, const std::string& name, const FileLoc& loc) {
    RGB c = params.get_rgb(name).value_or(RGB(1.f));
    if (c.r < 0 || c.g < 0 || c.b < 0)
        throw_input_error(loc_of(params, name, loc), "\"{}\" must not be negative", name);
    return c;
}

float get_scale(const ParameterList& params, const FileLoc& loc) {
    float s = params.get_float("scale", 1.f);
    if (!std::isfinite(s) || s < 0)
        throw_input_error(loc_of(params, "scale", loc), "\"scale\" must be non-negative");
    return s;
}

// A non-negative optional target ("power", "illuminance"); absent or zero: not used (pbrt-v4
// treats non-positive values as absent; we reject negative ones as a likely mistake).
float get_target(const ParameterList& params, const std::string& name, const FileLoc& loc) {
    float v = params.get_float(name, -1.f);
    if (!params.has(name)) return 0.f;
    if (!std::isfinite(v) || v < 0)
        throw_input_error(loc_of(params, name, loc), "\"{}\" must be non-negative", name);
    return v;
}

// pbrt-v4 rescales by target / k_e, where k_e is the power (or illuminance) of the unscaled
// spectrum's illuminant, i.e. 1 per unit of RGB here.
float rescale(float target, float k_e) { return target > 0 && k_e > 0 ? target / k_e : 1.f; }

std::unique_ptr<Light> create_infinite(const ParameterList& params, const Transform& to_world,
                                       const std::string& base_dir, const FileLoc& loc) {
    if (const Param* portal = params.find("portal"))
        throw_input_error(portal->loc, "infinite light: \"portal\" is not supported by manylight");
    float scale = get_scale(params, loc);
    std::string filename = params.get_string("filename", "");
    bool has_L = params.has("L");
    float E = get_target(params, "illuminance", loc);
    if (filename.empty()) {
        RGB L = get_color(params, "L", loc);
        // A constant L gives illuminance pi L on any surface.
        return make_uniform_infinite_light(L * (scale * rescale(E, kPi)));
    }
    if (has_L)
        throw_input_error(loc_of(params, "L", loc),
                          "infinite light: cannot specify both \"L\" and \"filename\"");
    std::filesystem::path path(filename);
    if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
    const FileLoc& floc = loc_of(params, "filename", loc);
    Image image = read_image(path.string(), floc);
    // The rule: square images are pbrt-v4's equal-area octahedral maps; 2:1 images are
    // latitude-longitude maps; anything else is an error.
    EnvMapping mapping;
    if (image.width == image.height)
        mapping = EnvMapping::EqualArea;
    else if (image.width == 2 * image.height)
        mapping = EnvMapping::LatLong;
    else
        throw_input_error(floc,
                          "infinite light \"{}\": image is {}x{}; expected a square (equal-area) "
                          "or 2:1 (latitude-longitude) image",
                          filename, image.width, image.height);
    if (image.low_dynamic_range)
        for (RGB& c : image.pixels)
            c = RGB(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b));
    if (E > 0) {
        float k_e = image_upper_hemisphere_illuminance(image, mapping);
        if (k_e > 0) scale *= E / k_e;
    }
    return make_image_infinite_light(std::move(image), mapping, to_world, scale);
}

}  // namespace

std::unique_ptr<Light> create_light(const std::string& type, const ParameterList& params,
                                    const Transform& light_to_world, const std::string& base_dir,
                                    const FileLoc& loc) {
    if (type == "point") {
        RGB I = get_color(params, "I", loc);
        float scale = get_scale(params, loc) * rescale(get_target(params, "power", loc), 4 * kPi);
        Vec3 from = params.get_point3("from").value_or(Vec3(0, 0, 0));
        return make_point_light(light_to_world.point(from), I * scale);
    }
    if (type == "spot") {
        RGB I = get_color(params, "I", loc);
        float scale = get_scale(params, loc);
        float power = get_target(params, "power", loc);
        Vec3 from = params.get_point3("from").value_or(Vec3(0, 0, 0));
        Vec3 to = params.get_point3("to").value_or(Vec3(0, 0, 1));
        float cone = params.get_float("coneangle", 30.f);
        // pbrt-v4's name; "conedelta" (no such pbrt-v4 parameter) stays an error, with a hint.
        if (const Param* wrong = params.find("conedelta"))
            throw_input_error(wrong->loc,
                              "spot light: pbrt-v4 has no \"conedelta\"; the falloff angle is "
                              "\"float conedeltaangle\"");
        float delta = params.get_float("conedeltaangle", 5.f);
        if (!(cone > 0 && cone <= 180))
            throw_input_error(loc_of(params, "coneangle", loc),
                              "spot light: \"coneangle\" must be in (0, 180], got {}", cone);
        if (!(delta >= 0 && delta <= cone))
            throw_input_error(loc_of(params, "conedeltaangle", loc),
                              "spot light: \"conedeltaangle\" must be in [0, coneangle], got {}",
                              delta);
        Vec3 axis = light_to_world.vector(to - from);
        if (!(length_squared(axis) > 0))
            throw_input_error(loc, "spot light: \"from\" and \"to\" must differ");
        float cos_end = std::cos(radians(cone));
        float cos_start = std::cos(radians(cone - delta));
        scale *= rescale(power, 2 * kPi * (1 - 0.5f * (cos_start + cos_end)));
        return make_spot_light(light_to_world.point(from), normalize(axis), I * scale, cos_start,
                               cos_end);
    }
    if (type == "distant") {
        RGB L = get_color(params, "L", loc);
        // Illuminance on a surface facing a distant light is L itself.
        float scale = get_scale(params, loc) * rescale(get_target(params, "illuminance", loc), 1);
        Vec3 from = params.get_point3("from").value_or(Vec3(0, 0, 0));
        Vec3 to = params.get_point3("to").value_or(Vec3(0, 0, 1));
        Vec3 w = light_to_world.vector(from - to);
        if (!(length_squared(w) > 0))
            throw_input_error(loc, "distant light: \"from\" and \"to\" must differ");
        return make_distant_light(normalize(w), L * scale);
    }
    if (type == "infinite") return create_infinite(params, light_to_world, base_dir, loc);
    if (type == "goniometric" || type == "projection")
        throw_input_error(loc, "the pbrt-v4 light \"{}\" is not supported by manylight", type);
    throw_input_error(loc, "unknown light type \"{}\"", type);
}

std::unique_ptr<Light> create_area_light(const std::string& type, const ParameterList& params,
                                         const TriangleMesh* mesh, const FileLoc& loc) {
    if (type != "diffuse") throw_input_error(loc, "unknown area light type \"{}\"", type);
    if (params.has("filename"))
        throw_input_error(loc_of(params, "filename", loc),
                          "area light: image \"filename\" is not supported");
    RGB L = get_color(params, "L", loc);
    float scale = get_scale(params, loc);
    bool two_sided = params.get_bool("twosided", false);
    float power = get_target(params, "power", loc);
    if (power > 0 && mesh) {
        double area = 0;
        for (size_t i = 0; i < mesh->triangle_count(); ++i) area += mesh->triangle_area(i);
        scale *= rescale(power, float(kPi * area * (two_sided ? 2 : 1)));
    }
    return make_diffuse_area_light(mesh, L * scale, two_sided);
}

}  // namespace ml
