// The LightSource / AreaLightSource factories: pbrt-v4 parameter names and defaults. RGB values
// are RGB radiometric quantities directly: pbrt-v4's photometric normalisation of RGB illuminants
// divides by the illuminant's luminance only, which cancels in an RGB renderer, so "power" and
// "illuminance" rescale the given colour exactly as pbrt-v4 does.
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>

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

// The image a light names, resolved against the scene's folder, linear (8-bit files are taken as
// sRGB-encoded, as pbrt-v4 takes them) and checked for values a light cannot emit.
Image read_light_image(const ParameterList& params, const std::string& what,
                       const std::string& base_dir, const FileLoc& loc, std::string* name) {
    *name = params.get_string("filename", "");
    if (name->empty()) throw_input_error(loc, "{}: \"filename\" is required", what);
    std::filesystem::path path(*name);
    if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
    const FileLoc& floc = loc_of(params, "filename", loc);
    Image image = read_image(path.string(), floc);
    if (image.width <= 0 || image.height <= 0)
        throw_input_error(floc, "{} \"{}\": the image is empty", what, *name);
    for (RGB& c : image.pixels) {
        if (!c.is_finite())
            throw_input_error(floc, "{} \"{}\": the image has infinite or NaN pixels", what, *name);
        if (image.low_dynamic_range)
            c = RGB(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b));
    }
    return image;
}

std::unique_ptr<Light> create_goniometric(const ParameterList& params, const Transform& to_world,
                                          const std::string& base_dir, const FileLoc& loc) {
    RGB I = get_color(params, "I", loc);
    float scale = get_scale(params, loc);
    float power = get_target(params, "power", loc);
    std::string name;
    Image image = read_light_image(params, "goniometric light", base_dir, loc, &name);
    if (image.width != image.height)
        throw_input_error(loc_of(params, "filename", loc),
                          "goniometric light \"{}\": image is {}x{}; expected a square "
                          "(equal-area) image",
                          name, image.width, image.height);
    // Relative intensity: the channels' average (a grey image's value), as pbrt-v4 reads RGB.
    std::vector<float> values(image.pixels.size());
    double sum = 0;
    for (size_t i = 0; i < values.size(); ++i) {
        const RGB& c = image.pixels[i];
        values[i] = std::max(0.f, (c.r + c.g + c.b) / 3);
        sum += double(values[i]);
    }
    // "power": the map's mean over the sphere's 4 pi sr (pbrt-v4 leaves I's colour out).
    scale *= rescale(power, float(4 * kPi * sum / double(values.size())));
    // pbrt-v4 reads the map in light space with y and z swapped: its centre is the light's +y.
    const float swap_yz[4][4] = {{1, 0, 0, 0}, {0, 0, 1, 0}, {0, 1, 0, 0}, {0, 0, 0, 1}};
    return make_goniometric_light(to_world * Transform::from_matrix(swap_yz), I * scale,
                                  std::move(values), image.width);
}

std::unique_ptr<Light> create_projection(const ParameterList& params, const Transform& to_world,
                                         const std::string& base_dir, const FileLoc& loc) {
    float scale = get_scale(params, loc);
    float power = get_target(params, "power", loc);
    float fov = params.get_float("fov", 90.f);
    if (!(fov > 0 && fov < 180))
        throw_input_error(loc_of(params, "fov", loc),
                          "projection light: \"fov\" must be in (0, 180), got {}", fov);
    std::string name;
    Image image = read_light_image(params, "projection light", base_dir, loc, &name);
    for (RGB& c : image.pixels) c = clamp_zero(c);
    if (power > 0) {
        // pbrt-v4's k_e: the luminance the image sends over its solid angle, each pixel by the
        // solid angle at its centre.
        int w = image.width, h = image.height;
        float aspect = float(w) / float(h), t = std::tan(radians(fov) / 2);
        float hx = aspect > 1 ? aspect : 1, hy = aspect > 1 ? 1 : 1 / aspect;
        double sum = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float sx = hx * (2 * (float(x) + 0.5f) / float(w) - 1);
                float sy = hy * (2 * (float(y) + 0.5f) / float(h) - 1);
                float cos_theta = normalize(Vec3(sx * t, sy * t, 1)).z;
                sum += double(image.at(x, y).luminance() * cos_theta * cos_theta * cos_theta);
            }
        scale *= rescale(power, float(4 * t * t * hx * hy * sum / double(w * h)));
    }
    for (RGB& c : image.pixels) c = c * scale;
    return make_projection_light(to_world, std::move(image), fov);
}

std::unique_ptr<Light> create_infinite(const ParameterList& params, const Transform& to_world,
                                       const std::string& base_dir, const FileLoc& loc) {
    // pbrt-v4's portal: four world-space corners of a rectangle (not moved by the CTM).
    std::optional<std::array<Vec3, 4>> portal;
    if (const Param* p = params.find("portal")) {
        std::vector<Vec3> c = params.get_point3s("portal");
        if (c.size() != 4)
            throw_input_error(p->loc, "infinite light: \"portal\" needs 4 points, got {}",
                              c.size());
        // pbrt-v4's test: opposite edges parallel, corners square (to 0.001). Written so that a
        // corner out of float range or a repeated corner (NaN edges) fails it too.
        Vec3 e01 = normalize(c[1] - c[0]), e12 = normalize(c[2] - c[1]);
        Vec3 e32 = normalize(c[2] - c[3]), e03 = normalize(c[3] - c[0]);
        const bool rectangle =
            std::abs(dot(e01, e32) - 1) <= 1e-3f && std::abs(dot(e12, e03) - 1) <= 1e-3f &&
            std::abs(dot(e01, e12)) <= 1e-3f && std::abs(dot(e12, e32)) <= 1e-3f &&
            std::abs(dot(e32, e03)) <= 1e-3f && std::abs(dot(e03, e01)) <= 1e-3f;
        if (!rectangle)
            throw_input_error(p->loc,
                              "infinite light: the \"portal\" is not a rectangle (its corners "
                              "go around it in order)");
        portal = std::array<Vec3, 4>{c[0], c[1], c[2], c[3]};
    }
    float scale = get_scale(params, loc);
    std::string filename = params.get_string("filename", "");
    bool has_L = params.has("L");
    float E = get_target(params, "illuminance", loc);
    if (filename.empty() && portal) {
        // As pbrt-v4: a constant L through a portal is a one-pixel map.
        Image image(1, 1);
        image.at(0, 0) = get_color(params, "L", loc);
        if (E > 0) {
            float k_e = image_upper_hemisphere_illuminance(image, EnvMapping::EqualArea);
            if (k_e > 0) scale *= E / k_e;
        }
        for (RGB& c : image.pixels) c = clamp_zero(c * scale);
        return make_portal_infinite_light(image, to_world, *portal);
    }
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
    if (portal) {
        if (mapping != EnvMapping::EqualArea)
            throw_input_error(floc,
                              "infinite light \"{}\": a portal needs a square (equal-area) image, "
                              "as in pbrt-v4; this one is {}x{}",
                              filename, image.width, image.height);
        for (RGB& c : image.pixels) c = clamp_zero(c * scale);
        return make_portal_infinite_light(image, to_world, *portal);
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
    if (type == "goniometric") return create_goniometric(params, light_to_world, base_dir, loc);
    if (type == "projection") return create_projection(params, light_to_world, base_dir, loc);
    throw_input_error(loc, "unknown light type \"{}\"", type);
}

std::unique_ptr<Light> create_area_light(const std::string& type, const ParameterList& params,
                                         const TriangleMesh* mesh, const FileLoc& loc,
                                         const std::string& base_dir) {
    if (type != "diffuse") throw_input_error(loc, "unknown area light type \"{}\"", type);
    float scale = get_scale(params, loc);
    bool two_sided = params.get_bool("twosided", false);
    float power = get_target(params, "power", loc);
    double area = 0;
    if (mesh)
        for (size_t i = 0; i < mesh->triangle_count(); ++i) area += mesh->triangle_area(i);
    float sides = two_sided ? 2.f : 1.f;
    if (params.has("filename")) {
        if (params.has("L"))
            throw_input_error(loc_of(params, "L", loc),
                              "area light: cannot specify both \"L\" and \"filename\"");
        std::string name;
        Image image = read_light_image(params, "area light", base_dir, loc, &name);
        if (power > 0) {
            // pbrt-v4's k_e: the image's mean luminance (negative pixels included) over the
            // emitting area.
            double lum = 0;
            for (const RGB& c : image.pixels) lum += double(c.luminance());
            lum /= double(image.pixels.size());
            scale *= rescale(power, float(kPi * area * lum * sides));
        }
        for (RGB& c : image.pixels) c = c * scale;
        return make_image_area_light(mesh, std::move(image), two_sided);
    }
    RGB L = get_color(params, "L", loc);
    if (power > 0 && mesh) scale *= rescale(power, float(kPi * area * sides));
    return make_diffuse_area_light(mesh, L * scale, two_sided);
}

}  // namespace ml
