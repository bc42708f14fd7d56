// The syntax of pbrt-v4 scene files: a stack of tokenizers for Include/Import, parameter lists,
// and one case per directive, handing the meaning to SceneBuilder.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "scene/scene_builder.h"
#include "scene/scene_desc.h"
#include "scene/tokenizer.h"

namespace ml {

namespace {

namespace fs = std::filesystem;

enum class ValueKind { Number, Integer, String, Bool, Spectrum };

bool param_kind(std::string_view type, ValueKind* kind) {
    static const char* numeric[] = {"float",   "point2", "vector2", "point3",
                                    "vector3", "point",  "vector",  "normal",
                                    "normal3", "rgb",    "color",   "blackbody"};
    for (const char* t : numeric)
        if (type == t) return *kind = ValueKind::Number, true;
    if (type == "integer") return *kind = ValueKind::Integer, true;
    if (type == "string" || type == "texture") return *kind = ValueKind::String, true;
    if (type == "bool") return *kind = ValueKind::Bool, true;
    if (type == "spectrum") return *kind = ValueKind::Spectrum, true;
    return false;
}

std::string canonical(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::path(path).lexically_normal().string() : p.string();
}

class Parser {
public:
    Parser(std::unique_ptr<Tokenizer> main, std::string base_dir, std::string main_canonical)
        : m_base_dir(base_dir), m_builder(std::move(base_dir)) {
        m_open.push_back(std::move(main_canonical));
        m_files.push_back(std::move(main));
    }

    SceneDesc parse() {
        for (;;) {
            Token t = next();
            if (t.kind == TokenKind::End) break;
            if (t.kind != TokenKind::Word) syntax_error(t, "expected a directive");
            directive(t);
        }
        return m_builder.finish();
    }

private:
    // ---- Tokens, across included files. ----

    Token next() {
        if (m_peeked) {
            Token t = std::move(*m_peeked);
            m_peeked.reset();
            return t;
        }
        for (;;) {
            Token t = m_files.back()->next();
            if (t.kind != TokenKind::End || m_files.size() == 1) return t;
            // An included file ends: its tokens may still be referenced, so keep its text.
            m_done.push_back(std::move(m_files.back()));
            m_files.pop_back();
            m_open.pop_back();
        }
    }
    const Token& peek() {
        if (!m_peeked) m_peeked = next();
        return *m_peeked;
    }

    [[noreturn]] static void syntax_error(const Token& t, const std::string& what) {
        std::string found = t.kind == TokenKind::End      ? "the end of the file"
                            : t.kind == TokenKind::String ? fmt::format("\"{}\"", t.value())
                                                          : fmt::format("'{}'", t.raw);
        throw InputError(Tokenizer::loc(t), fmt::format("syntax error: {}, found {}", what, found));
    }

    std::string expect_string(const Token& directive, const char* what) {
        Token t = next();
        if (t.kind != TokenKind::String)
            syntax_error(t, fmt::format("{} expects a quoted {}", directive.raw, what));
        return std::string(t.value());
    }

    double expect_number(const Token& directive) {
        Token t = next();
        double v = 0;
        if (t.kind != TokenKind::Word)
            syntax_error(t, fmt::format("{} expects a number", directive.raw));
        if (!parse_number(t.raw, &v))
            throw InputError(Tokenizer::loc(t), fmt::format("bad number '{}'", t.raw));
        return v;
    }

    Vec3 expect_vec3(const Token& directive) {
        float x = float(expect_number(directive));
        float y = float(expect_number(directive));
        float z = float(expect_number(directive));
        return Vec3(x, y, z);
    }

    void expect_matrix(const Token& directive, double m[16]) {
        Token open = next();
        if (open.kind != TokenKind::LBracket)
            syntax_error(open, fmt::format("{} expects '[' and 16 numbers", directive.raw));
        for (int i = 0; i < 16; ++i) m[i] = expect_number(directive);
        Token close = next();
        if (close.kind != TokenKind::RBracket)
            syntax_error(close, fmt::format("{} expects ']' after 16 numbers", directive.raw));
    }

    // ---- Parameter lists: "type name" value | [ values ]. ----

    static void add_value(Param& p, ValueKind kind, const Token& t) {
        if (t.kind == TokenKind::String) {
            if (kind == ValueKind::Bool) {
                if (t.value() != "true" && t.value() != "false")
                    throw InputError(
                        Tokenizer::loc(t),
                        fmt::format("parameter \"{} {}\": expected true or false", p.type, p.name));
                p.bools.push_back(t.value() == "true");
                return;
            }
            if (kind != ValueKind::String && kind != ValueKind::Spectrum)
                throw InputError(Tokenizer::loc(t),
                                 fmt::format("parameter \"{} {}\" expects numbers, found a string",
                                             p.type, p.name));
            p.strings.emplace_back(t.value());
            return;
        }
        if (kind == ValueKind::Bool) {
            if (t.raw != "true" && t.raw != "false")
                throw InputError(
                    Tokenizer::loc(t),
                    fmt::format("parameter \"{} {}\": expected true or false, found '{}'", p.type,
                                p.name, t.raw));
            p.bools.push_back(t.raw == "true");
            return;
        }
        if (kind == ValueKind::String)
            throw InputError(Tokenizer::loc(t),
                             fmt::format("parameter \"{} {}\" expects quoted strings, found '{}'",
                                         p.type, p.name, t.raw));
        double v = 0;
        if (!parse_number(t.raw, &v))
            throw InputError(Tokenizer::loc(t), fmt::format("bad number '{}'", t.raw));
        if (kind == ValueKind::Integer && (v != std::floor(v) || std::abs(v) > 2147483647.0))
            throw InputError(Tokenizer::loc(t),
                             fmt::format("parameter \"{} {}\" expects integers, found '{}'", p.type,
                                         p.name, t.raw));
        p.numbers.push_back(v);
    }

    ParameterList parse_params(const FileLoc& loc) {
        ParameterList list(loc);
        while (peek().kind == TokenKind::String) {
            Token decl = next();
            Param p;
            p.loc = Tokenizer::loc(decl);
            std::string_view d = decl.value();
            size_t a = d.find_first_not_of(" \t");
            size_t b = a == d.npos ? d.npos : d.find_first_of(" \t", a);
            size_t c = b == d.npos ? d.npos : d.find_first_not_of(" \t", b);
            size_t e = c == d.npos ? d.npos : d.find_first_of(" \t", c);
            if (c == d.npos || (e != d.npos && d.find_first_not_of(" \t", e) != d.npos))
                throw InputError(p.loc, fmt::format("bad parameter declaration \"{}\": expected "
                                                    "\"type name\"",
                                                    d));
            p.type = std::string(d.substr(a, b - a));
            p.name = std::string(d.substr(c, e == d.npos ? d.npos : e - c));
            ValueKind kind;
            if (!param_kind(p.type, &kind))
                throw InputError(p.loc,
                                 fmt::format("unknown parameter type \"{}\" in \"{}\"", p.type, d));
            Token v = next();
            if (v.kind == TokenKind::LBracket) {
                for (;;) {
                    Token t = next();
                    if (t.kind == TokenKind::RBracket) break;
                    if (t.kind == TokenKind::End)
                        throw InputError(
                            Tokenizer::loc(v),
                            fmt::format("parameter \"{}\": '[' without a matching ']'", d));
                    if (t.kind == TokenKind::LBracket)
                        syntax_error(t,
                                     fmt::format("parameter \"{}\": expected values and ']'", d));
                    add_value(p, kind, t);
                }
            } else if (v.kind == TokenKind::String || v.kind == TokenKind::Word) {
                add_value(p, kind, v);
            } else {
                syntax_error(v, fmt::format("parameter \"{}\" expects a value", d));
            }
            list.add(std::move(p));
        }
        return list;
    }

    // ---- Include / Import. ----

    void include(const Token& directive) {
        std::string name = expect_string(directive, "file name");
        FileLoc loc = Tokenizer::loc(directive);
        // As pbrt-v4: relative to the directory of the main scene file.
        fs::path path(name);
        if (path.is_relative()) path = fs::path(m_base_dir) / path;
        std::string file = path.lexically_normal().string();
        std::string canon = canonical(file);
        for (const std::string& open : m_open)
            if (open == canon)
                throw_input_error(loc,
                                  "{} \"{}\" includes a file that is already being read "
                                  "(an include cycle)",
                                  std::string(directive.raw), name);
        std::error_code ec;
        if (!fs::exists(file, ec))
            throw_input_error(loc, "{} \"{}\": no such file ({})", std::string(directive.raw), name,
                              file);
        auto t = std::make_unique<Tokenizer>(Tokenizer::from_file(file, loc));
        if (m_peeked) throw_input_error(loc, "internal error: include with a token pending");
        m_files.push_back(std::move(t));
        m_open.push_back(std::move(canon));
    }

    void directive(const Token& t);

    std::string m_base_dir;
    SceneBuilder m_builder;
    std::vector<std::unique_ptr<Tokenizer>> m_files, m_done;
    std::vector<std::string> m_open;  // canonical paths of the files being read, for cycles
    std::optional<Token> m_peeked;
};

void Parser::directive(const Token& t) {
    const std::string_view d = t.raw;
    const std::string name(d);
    const FileLoc loc = Tokenizer::loc(t);
    SceneBuilder& b = m_builder;
    auto world = [&] { b.require_world(name, loc); };
    auto options = [&] { b.require_options(name, loc); };

    // Transforms (allowed in both blocks).
    if (d == "Identity") {
        b.identity();
    } else if (d == "Translate") {
        b.translate(expect_vec3(t));
    } else if (d == "Scale") {
        Vec3 s = expect_vec3(t);
        if (s.x == 0.f || s.y == 0.f || s.z == 0.f)
            throw_input_error(loc, "Scale by zero makes the transform singular");
        b.scale(s);
    } else if (d == "Rotate") {
        float angle = float(expect_number(t));
        b.rotate(angle, expect_vec3(t), loc);
    } else if (d == "LookAt") {
        Vec3 eye = expect_vec3(t), look = expect_vec3(t), up = expect_vec3(t);
        b.look_at(eye, look, up, loc);
    } else if (d == "Transform" || d == "ConcatTransform") {
        double m[16];
        expect_matrix(t, m);
        if (d == "Transform")
            b.transform(m, loc);
        else
            b.concat_transform(m, loc);
    } else if (d == "CoordinateSystem") {
        b.coordinate_system(expect_string(t, "name"));
    } else if (d == "CoordSysTransform") {
        b.coord_sys_transform(expect_string(t, "name"), loc);
    } else if (d == "ReverseOrientation") {
        b.reverse_orientation();
    } else if (d == "AttributeBegin" || d == "TransformBegin") {
        b.begin_scope(d == "AttributeBegin" ? ScopeKind::Attribute : ScopeKind::Transform, loc);
    } else if (d == "AttributeEnd" || d == "TransformEnd") {
        b.end_scope(d == "AttributeEnd" ? ScopeKind::Attribute : ScopeKind::Transform, loc);
    } else if (d == "Include" || d == "Import") {
        include(t);
    } else if (d == "ColorSpace") {
        Token n = next();
        if (n.kind != TokenKind::String) syntax_error(n, "ColorSpace expects a quoted name");
        if (n.value() != "srgb")
            throw InputError(
                Tokenizer::loc(n),
                fmt::format("unsupported color space \"{}\" (only \"srgb\")", n.value()));
    } else if (d == "Camera") {
        options();
        std::string type = expect_string(t, "camera type");
        b.camera(type, parse_params(loc), loc);
    } else if (d == "Film" || d == "Sampler" || d == "PixelFilter" || d == "Integrator" ||
               d == "Accelerator") {
        options();
        std::string type = expect_string(t, "type");
        ParameterList params = parse_params(loc);
        // One accelerator serves every scene: its settings are accepted and ignored.
        if (d == "Film") b.entity(&SceneDesc::film, type, std::move(params), loc);
        if (d == "Sampler") b.entity(&SceneDesc::sampler, type, std::move(params), loc);
        if (d == "PixelFilter") b.entity(&SceneDesc::filter, type, std::move(params), loc);
        if (d == "Integrator") b.entity(&SceneDesc::integrator, type, std::move(params), loc);
    } else if (d == "WorldBegin") {
        b.world_begin(loc);
    } else if (d == "WorldEnd") {
        // pbrt-v3's terminator; pbrt-v4 drops it. Accepted for old files.
        world();
    } else if (d == "Shape") {
        world();
        std::string type = expect_string(t, "shape type");
        ParameterList params = parse_params(loc);
        b.apply_attributes("shape", params);
        b.shape(type, params, loc);
    } else if (d == "Material") {
        world();
        std::string type = expect_string(t, "material type");
        ParameterList params = parse_params(loc);
        b.apply_attributes("material", params);
        b.material(type, params, loc);
    } else if (d == "MakeNamedMaterial") {
        world();
        std::string n = expect_string(t, "material name");
        ParameterList params = parse_params(loc);
        b.apply_attributes("material", params);
        b.make_named_material(n, params, loc);
    } else if (d == "NamedMaterial") {
        world();
        b.named_material(expect_string(t, "material name"), loc);
    } else if (d == "Texture") {
        world();
        std::string n = expect_string(t, "texture name");
        std::string kind = expect_string(t, "texture type (\"float\" or \"spectrum\")");
        std::string cls = expect_string(t, "texture class");
        ParameterList params = parse_params(loc);
        b.apply_attributes("texture", params);
        b.texture(n, kind, cls, params, loc);
    } else if (d == "LightSource") {
        world();
        std::string type = expect_string(t, "light type");
        ParameterList params = parse_params(loc);
        b.apply_attributes("light", params);
        b.light_source(type, params, loc);
    } else if (d == "AreaLightSource") {
        world();
        std::string type = expect_string(t, "area light type");
        ParameterList params = parse_params(loc);
        b.apply_attributes("light", params);
        b.area_light_source(type, std::move(params), loc);
    } else if (d == "ObjectBegin") {
        world();
        b.object_begin(expect_string(t, "object name"), loc);
    } else if (d == "ObjectEnd") {
        world();
        b.object_end(loc);
    } else if (d == "ObjectInstance") {
        world();
        b.object_instance(expect_string(t, "object name"), loc);
    } else if (d == "Attribute") {
        world();
        std::string target = expect_string(t, "target (shape, light, material, texture)");
        b.attribute(target, parse_params(loc), loc);
    } else if (d == "ActiveTransform") {
        // pbrt-v4 writes the name unquoted: ActiveTransform StartTime.
        Token n = next();
        if (n.kind != TokenKind::Word)
            syntax_error(n, "ActiveTransform expects StartTime, EndTime or All");
        b.active_transform(std::string(n.raw), Tokenizer::loc(n));
    } else if (d == "TransformTimes") {
        options();
        double start = expect_number(t);
        double end = expect_number(t);
        b.transform_times(start, end, loc);
    } else if (d == "Option") {
        // pbrt-v4: Option "name" value, the value a bare word (true, 4) or a quoted string.
        std::string n = expect_string(t, "option name");
        Token v = next();
        if (v.kind != TokenKind::Word && v.kind != TokenKind::String)
            syntax_error(v, "Option expects a value after its name");
        b.option(n, std::string(v.kind == TokenKind::String ? v.value() : v.raw),
                 v.kind == TokenKind::String, loc);
    } else if (d == "MakeNamedMedium") {
        std::string n = expect_string(t, "medium name");
        b.make_named_medium(n, parse_params(loc), loc);
    } else if (d == "MediumInterface") {
        // One name: both sides; two: inside, then outside.
        std::string inside = expect_string(t, "medium name");
        std::string outside = inside;
        if (peek().kind == TokenKind::String) outside = expect_string(t, "outside medium name");
        b.medium_interface(inside, outside, loc);
    } else {
        double v;
        if (parse_number(d, &v))
            syntax_error(t, "expected a directive (a number outside a parameter list?)");
        throw_input_error(loc, "unknown directive \"{}\"", name);
    }
}

}  // namespace

SceneDesc parse_scene_file(const std::string& path) {
    auto main = std::make_unique<Tokenizer>(Tokenizer::from_file(path, FileLoc{path}));
    fs::path dir = fs::path(path).parent_path();
    std::string base = dir.empty() ? std::string(".") : dir.string();
    Parser parser(std::move(main), base, canonical(path));
    return parser.parse();
}

SceneDesc parse_scene_string(const std::string& text, const std::string& base_dir,
                             const std::string& name) {
    auto main = std::make_unique<Tokenizer>(text, name);
    // A name that is not a file cannot take part in an include cycle.
    Parser parser(std::move(main), base_dir, "\n" + name);
    return parser.parse();
}

}  // namespace ml
