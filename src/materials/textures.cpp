// Texture lookups and the `Texture` directive's factory.
#include "materials/textures.h"

#include <cmath>
#include <filesystem>

#include "materials/create.h"
#include "materials/procedural_textures.h"

namespace ml {

// ---- image lookups ----

RGB ImageLookup::texel(int x, int y) const {
    const int w = m_image->width, h = m_image->height;
    switch (m_wrap) {
        case WrapMode::Repeat:
            x %= w;
            y %= h;
            if (x < 0) x += w;
            if (y < 0) y += h;
            break;
        case WrapMode::Clamp:
            x = std::clamp(x, 0, w - 1);
            y = std::clamp(y, 0, h - 1);
            break;
        case WrapMode::Black:
            if (x < 0 || x >= w || y < 0 || y >= h) return RGB();
            break;
    }
    return m_image->at(x, y);
}

// ---- mappings ----

Vec2 TextureMapping2D::map(const TextureEvalContext& ctx) const {
    if (kind == Kind::UV) return {su * ctx.uv.x + du, sv * ctx.uv.y + dv};
    Vec3 p = world_to_texture.point(ctx.p);
    switch (kind) {
        case Kind::Spherical: {
            float len = length(p);
            if (!(len > 0)) return {0, 0};
            Vec3 w = p / len;
            float theta = std::acos(std::clamp(w.z, -1.f, 1.f));
            float phi = std::atan2(w.y, w.x);
            if (phi < 0) phi += 2 * kPi;
            return {theta / kPi, phi / (2 * kPi)};
        }
        case Kind::Cylindrical:
            return {(kPi + std::atan2(p.y, p.x)) / (2 * kPi), p.z};
        case Kind::Planar:
            return {du + dot(p, v1), dv + dot(p, v2)};
        case Kind::UV:
            break;
    }
    return ctx.uv;
}

bool Checkerboard::second(const TextureEvalContext& ctx) const {
    if (dimension == 3) {
        Vec3 p = world_to_texture.point(ctx.p);
        int64_t sum =
            int64_t(std::floor(p.x)) + int64_t(std::floor(p.y)) + int64_t(std::floor(p.z));
        return (sum & 1) != 0;
    }
    Vec2 st = map2d.map(ctx);
    int64_t sum = int64_t(std::floor(st.x)) + int64_t(std::floor(st.y));
    return (sum & 1) != 0;
}

RGB ImageLookup::lookup(const TextureEvalContext& ctx) const {
    Vec2 st = m_mapping.map(ctx);
    st.y = 1 - st.y;  // image rows run top to bottom; v runs bottom to top
    float x = st.x * m_image->width, y = st.y * m_image->height;
    if (m_point) return texel(int(std::floor(x)), int(std::floor(y)));
    // Bilinear between the four nearest texel centres.
    x -= 0.5f;
    y -= 0.5f;
    float fx = std::floor(x), fy = std::floor(y);
    int xi = int(fx), yi = int(fy);
    float dx = x - fx, dy = y - fy;
    return texel(xi, yi) * ((1 - dx) * (1 - dy)) + texel(xi + 1, yi) * (dx * (1 - dy)) +
           texel(xi, yi + 1) * ((1 - dx) * dy) + texel(xi + 1, yi + 1) * (dx * dy);
}

RGB ImageRGBTexture::eval(const TextureEvalContext& ctx) const {
    RGB v = m_lookup.lookup(ctx) * m_scale;
    return clamp_zero(m_invert ? RGB(1) - v : v);
}

float ImageFloatTexture::eval(const TextureEvalContext& ctx) const {
    float v = m_lookup.lookup(ctx).r * m_scale;
    return m_invert ? std::max(0.f, 1 - v) : v;
}

// ---- loading ----

std::shared_ptr<const Image> ImageCache::get(const std::string& path, const FileLoc& loc) {
    auto it = images.find(path);
    if (it != images.end()) return it->second;
    auto img = std::make_shared<const Image>(read_image(path, loc));
    images[path] = img;
    return img;
}

std::string resolve_path(const std::string& name, const std::string& base_dir) {
    std::filesystem::path p(name);
    if (p.is_absolute() || base_dir.empty()) return name;
    return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

namespace {

struct Encoding {
    enum Kind { Linear, SRGB, Gamma } kind = Linear;
    float gamma = 1;
    std::string key() const {
        return kind == Linear ? "linear" : kind == SRGB ? "sRGB" : "gamma " + std::to_string(gamma);
    }
};

Encoding parse_encoding(const std::string& s, const FileLoc& loc) {
    if (s == "linear") return {Encoding::Linear, 1};
    if (s == "sRGB") return {Encoding::SRGB, 1};
    if (s.rfind("gamma ", 0) == 0) {
        try {
            size_t used = 0;
            float g = std::stof(s.substr(6), &used);
            if (used == s.size() - 6 && g > 0 && std::isfinite(g)) return {Encoding::Gamma, g};
        } catch (const std::exception&) {
        }
    }
    throw_input_error(loc,
                      "unknown color encoding \"{}\" (expected \"sRGB\", \"linear\" or "
                      "\"gamma <value>\")",
                      s);
}

bool has_extension(const std::string& path, const std::string& ext) {
    std::string e = std::filesystem::path(path).extension().string();
    if (e.size() != ext.size() + 1) return false;
    for (size_t i = 0; i < ext.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(e[i + 1])) != ext[i]) return false;
    return true;
}

// The image of `path` with linear values. pbrt-v4's rules, which we follow:
// - "encoding" defaults to "sRGB" for files named *.png and to "linear" for every other file;
// - the encoding only applies to integer-valued (8- or 16-bit) PNG data. Floating-point files
//   (EXR, PFM, HDR) are linear whatever it says, and pbrt-v4 reads other 8-bit formats (JPEG,
//   TGA, BMP ...) as sRGB regardless of it.
// The decode happens once per (file, encoding), into a float copy kept in the cache under a
// derived key; the raw 8-bit image is dropped from the cache once decoded.
std::shared_ptr<const Image> linear_image(ImageCache& cache, const std::string& path,
                                          const Encoding& requested, const FileLoc& loc) {
    Encoding enc = requested;
    if (!has_extension(path, "png")) enc = Encoding{Encoding::SRGB, 1};
    const std::string key = path + "\n[decoded " + enc.key() + "]";
    if (auto it = cache.images.find(key); it != cache.images.end()) return it->second;
    std::shared_ptr<const Image> raw = cache.get(path, loc);
    if (!raw->low_dynamic_range || enc.kind == Encoding::Linear) return raw;
    auto decoded = std::make_shared<Image>(*raw);
    decoded->low_dynamic_range = false;
    // 8-bit data has 256 values per channel: decode through a table, not a pow per texel.
    float table[256];
    for (int i = 0; i < 256; ++i) {
        float v = i / 255.f;
        table[i] = enc.kind == Encoding::SRGB ? srgb_to_linear(v) : std::pow(v, enc.gamma);
    }
    auto decode = [&](float v) {
        float s = v * 255.f;
        int i = int(std::lround(s));
        if (i >= 0 && i <= 255 && std::abs(s - i) < 1e-3f) return table[i];
        v = std::clamp(v, 0.f, 1.f);  // 16-bit data
        return enc.kind == Encoding::SRGB ? srgb_to_linear(v) : std::pow(v, enc.gamma);
    };
    for (RGB& p : decoded->pixels) p = RGB(decode(p.r), decode(p.g), decode(p.b));
    cache.images.erase(path);
    cache.images[key] = decoded;
    return decoded;
}

const FileLoc& loc_of(const ParameterList& params, const std::string& name, const FileLoc& def) {
    for (const Param& p : params.params())
        if (p.name == name) return p.loc;
    return def;
}

TextureMapping2D parse_mapping(const ParameterList& params, const Transform& to_world,
                               const FileLoc& loc) {
    TextureMapping2D m;
    m.world_to_texture = to_world.inverse();
    std::string type = params.get_string("mapping", "uv");
    if (type == "uv") {
        m.su = params.get_float("uscale", 1);
        m.sv = params.get_float("vscale", 1);
        m.du = params.get_float("udelta", 0);
        m.dv = params.get_float("vdelta", 0);
    } else if (type == "spherical") {
        m.kind = TextureMapping2D::Kind::Spherical;
    } else if (type == "cylindrical") {
        m.kind = TextureMapping2D::Kind::Cylindrical;
    } else if (type == "planar") {
        m.kind = TextureMapping2D::Kind::Planar;
        m.v1 = params.get_point3("v1").value_or(Vec3(1, 0, 0));
        m.v2 = params.get_point3("v2").value_or(Vec3(0, 1, 0));
        m.du = params.get_float("udelta", 0);
        m.dv = params.get_float("vdelta", 0);
    } else {
        throw_input_error(loc_of(params, "mapping", loc),
                          "unknown texture mapping \"{}\" (uv, spherical, cylindrical or planar)",
                          type);
    }
    return m;
}

int noise_octaves_param(const ParameterList& params, const FileLoc& loc) {
    int octaves = params.get_int("octaves", 8);
    if (octaves < 1 || octaves > 32)
        throw_input_error(loc_of(params, "octaves", loc), "\"octaves\" must lie in [1, 32], got {}",
                          octaves);
    return octaves;
}

WrapMode parse_wrap(const std::string& s, const FileLoc& loc) {
    if (s == "repeat") return WrapMode::Repeat;
    if (s == "black") return WrapMode::Black;
    if (s == "clamp") return WrapMode::Clamp;
    throw_input_error(loc, "unknown wrap mode \"{}\" (expected repeat, black or clamp)", s);
}

ImageLookup make_image_lookup(const ParameterList& params, const Transform& to_world,
                              const std::string& base_dir, ImageCache& images, const FileLoc& loc) {
    TextureMapping2D mapping = parse_mapping(params, to_world, loc);
    std::string filter = params.get_string("filter", "bilinear");
    if (filter != "point" && filter != "bilinear" && filter != "trilinear" && filter != "ewa")
        throw_input_error(loc_of(params, "filter", loc),
                          "unknown texture filter \"{}\" (expected point, bilinear, trilinear or "
                          "ewa)",
                          filter);
    params.get_float("maxanisotropy", 8);  // accepted for EWA; we filter bilinearly
    WrapMode wrap = parse_wrap(params.get_string("wrap", "repeat"), loc_of(params, "wrap", loc));
    std::string filename = params.get_string("filename", "");
    if (filename.empty()) throw_input_error(loc, "imagemap texture needs a \"filename\"");
    std::string path = resolve_path(filename, base_dir);
    std::string enc_default = has_extension(path, "png") ? "sRGB" : "linear";
    Encoding enc =
        parse_encoding(params.get_string("encoding", enc_default), loc_of(params, "encoding", loc));
    auto image = linear_image(images, path, enc, loc_of(params, "filename", loc));
    if (image->width <= 0 || image->height <= 0)
        throw_input_error(loc, "image \"{}\" is empty", path);
    return ImageLookup(image, mapping, wrap, filter == "point");
}

}  // namespace

ImageLookup normal_map_lookup(ImageCache& images, const std::string& base_dir,
                              const std::string& filename, const FileLoc& loc) {
    const std::string path = resolve_path(filename, base_dir);
    auto image = linear_image(images, path, Encoding{Encoding::Linear, 1}, loc);
    if (image->width <= 0 || image->height <= 0)
        throw_input_error(loc, "normal map \"{}\" is empty", path);
    return ImageLookup(image, TextureMapping2D{}, WrapMode::Repeat, false);
}

void create_texture(const std::string& name, const std::string& kind, const std::string& cls,
                    const ParameterList& params, const std::string& base_dir,
                    NamedTextures& textures, ImageCache& images, const FileLoc& loc,
                    const Transform& to_world) {
    const bool is_float = kind == "float";
    if (!is_float && kind != "spectrum")
        throw_input_error(loc, "unknown texture kind \"{}\" (expected \"float\" or \"spectrum\")",
                          kind);

    // A named texture argument of a texture (e.g. "scale"'s "tex") or a constant value.
    auto float_arg = [&](const std::string& pname, float def) -> std::shared_ptr<FloatTexture> {
        const Param* p = params.find(pname);
        if (p && p->type == "texture") {
            std::string tname = params.get_texture(pname);
            auto it = textures.floats.find(tname);
            if (it == textures.floats.end())
                throw_input_error(p->loc, "undefined float texture \"{}\"", tname);
            return it->second;
        }
        return std::make_shared<ConstantFloatTexture>(params.get_float(pname, def));
    };
    auto rgb_arg = [&](const std::string& pname, RGB def) -> std::shared_ptr<RGBTexture> {
        const Param* p = params.find(pname);
        if (p && p->type == "texture") {
            std::string tname = params.get_texture(pname);
            if (auto it = textures.rgbs.find(tname); it != textures.rgbs.end()) return it->second;
            if (auto it = textures.floats.find(tname); it != textures.floats.end())
                return std::make_shared<FloatAsRGBTexture>(it->second);
            throw_input_error(p->loc, "undefined spectrum texture \"{}\"", tname);
        }
        if (p && p->type == "float")
            return std::make_shared<ConstantRGBTexture>(RGB(params.get_float(pname, 1)));
        return std::make_shared<ConstantRGBTexture>(params.get_rgb(pname).value_or(def));
    };

    // A value that may not be a texture (bilerp's corners).
    auto rgb_value = [&](const std::string& pname, RGB def) {
        if (const Param* p = params.find(pname); p && p->type == "float")
            return RGB(params.get_float(pname, 1));
        return params.get_rgb(pname).value_or(def);
    };

    if (cls == "constant") {
        if (is_float)
            textures.floats[name] = float_arg("value", 1);
        else
            textures.rgbs[name] = rgb_arg("value", RGB(1));
    } else if (cls == "scale") {
        auto scale = float_arg("scale", 1);
        if (is_float)
            textures.floats[name] = std::make_shared<ScaleFloatTexture>(float_arg("tex", 1), scale);
        else
            textures.rgbs[name] = std::make_shared<ScaleRGBTexture>(rgb_arg("tex", RGB(1)), scale);
    } else if (cls == "imagemap") {
        ImageLookup lookup = make_image_lookup(params, to_world, base_dir, images, loc);
        float scale = params.get_float("scale", 1);
        bool invert = params.get_bool("invert", false);
        if (is_float)
            textures.floats[name] = std::make_shared<ImageFloatTexture>(lookup, scale, invert);
        else
            textures.rgbs[name] = std::make_shared<ImageRGBTexture>(lookup, scale, invert);
    } else if (cls == "checkerboard") {
        Checkerboard board;
        board.dimension = params.get_int("dimension", 2);
        if (board.dimension != 2 && board.dimension != 3)
            throw_input_error(loc_of(params, "dimension", loc),
                              "checkerboard: \"dimension\" must be 2 or 3, got {}",
                              board.dimension);
        if (board.dimension == 2)
            board.map2d = parse_mapping(params, to_world, loc);
        else
            board.world_to_texture = to_world.inverse();
        if (is_float)
            textures.floats[name] = std::make_shared<CheckerboardFloatTexture>(
                board, float_arg("tex1", 1), float_arg("tex2", 0));
        else
            textures.rgbs[name] = std::make_shared<CheckerboardRGBTexture>(
                board, rgb_arg("tex1", RGB(1)), rgb_arg("tex2", RGB(0)));
    } else if (cls == "bilerp") {
        TextureMapping2D mapping = parse_mapping(params, to_world, loc);
        if (is_float)
            textures.floats[name] = std::make_shared<BilerpFloatTexture>(
                mapping, params.get_float("v00", 0), params.get_float("v01", 1),
                params.get_float("v10", 0), params.get_float("v11", 1));
        else
            textures.rgbs[name] = std::make_shared<BilerpRGBTexture>(
                mapping, rgb_value("v00", RGB(0)), rgb_value("v01", RGB(1)),
                rgb_value("v10", RGB(0)), rgb_value("v11", RGB(1)));
    } else if (cls == "dots") {
        // pbrt-v4 swaps the two (see DotsTexture): "outside" inside the dots.
        TextureMapping2D mapping = parse_mapping(params, to_world, loc);
        if (is_float)
            textures.floats[name] = std::make_shared<DotsFloatTexture>(
                mapping, float_arg("outside", 0), float_arg("inside", 1));
        else
            textures.rgbs[name] = std::make_shared<DotsRGBTexture>(
                mapping, rgb_arg("outside", RGB(0)), rgb_arg("inside", RGB(1)));
    } else if (cls == "fbm" || cls == "wrinkled" || cls == "windy") {
        if (!is_float)
            throw_input_error(loc, "\"{}\" is a float texture in pbrt-v4, not a spectrum one", cls);
        using Kind = NoiseTexture::Kind;
        Kind k = cls == "fbm" ? Kind::Fbm : cls == "wrinkled" ? Kind::Wrinkled : Kind::Windy;
        int octaves = k == Kind::Windy ? 0 : noise_octaves_param(params, loc);
        float omega = k == Kind::Windy ? 0 : params.get_float("roughness", .5f);
        textures.floats[name] =
            std::make_shared<NoiseTexture>(k, to_world.inverse(), octaves, omega);
    } else if (cls == "marble") {
        if (is_float)
            throw_input_error(loc, "\"marble\" is a spectrum texture in pbrt-v4, not a float one");
        int octaves = noise_octaves_param(params, loc);
        float omega = params.get_float("roughness", .5f);
        textures.rgbs[name] = std::make_shared<MarbleTexture>(to_world.inverse(), octaves, omega,
                                                              params.get_float("scale", 1),
                                                              params.get_float("variation", .2f));
    } else if (cls == "mix" || cls == "directionmix") {
        auto make = [&](auto tex1, auto tex2, auto base) {
            using Mix = MixTexture<typename decltype(base)::element_type,
                                   decltype(tex1->eval(TextureEvalContext{}))>;
            if (cls == "mix") return std::make_shared<Mix>(tex1, tex2, float_arg("amount", .5f));
            // The direction is in texture space, as pbrt-v4 reads it.
            Vec3 dir = to_world.vector(params.get_point3("dir").value_or(Vec3(0, 1, 0)));
            if (!(length_squared(dir) > 0))
                throw_input_error(loc_of(params, "dir", loc), "directionmix: \"dir\" is zero");
            return std::make_shared<Mix>(tex1, tex2, normalize(dir));
        };
        if (is_float)
            textures.floats[name] =
                make(float_arg("tex1", 0), float_arg("tex2", 1), std::shared_ptr<FloatTexture>());
        else
            textures.rgbs[name] = make(rgb_arg("tex1", RGB(0)), rgb_arg("tex2", RGB(1)),
                                       std::shared_ptr<RGBTexture>());
    } else if (cls == "ptex") {
        throw_input_error(loc, "the pbrt-v4 texture \"{}\" is not supported by manylight", cls);
    } else {
        throw_input_error(loc, "unknown texture class \"{}\"", cls);
    }
}

}  // namespace ml
