#include "scene/scene_builder.h"

#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>

#include "core/parallel.h"
#include "geometry/curves.h"
#include "geometry/loop_subdiv.h"
#include "geometry/ply.h"
#include "geometry/shapes.h"
#include "lights/create.h"
#include "materials/textures.h"
#include "scene/tokenizer.h"

namespace ml {

SceneBuilder::SceneBuilder(std::string base_dir) { m_desc.base_dir = std::move(base_dir); }

SceneBuilder::~SceneBuilder() {
    m_loads.cancel();
    m_loads.wait();
}

void SceneBuilder::require_options(const std::string& directive, const FileLoc& loc) const {
    if (m_in_world)
        throw_input_error(loc, "\"{}\" is not allowed after WorldBegin (it belongs before it)",
                          directive);
}

void SceneBuilder::require_world(const std::string& directive, const FileLoc& loc) const {
    if (!m_in_world) throw_input_error(loc, "\"{}\" is only allowed after WorldBegin", directive);
}

void SceneBuilder::rotate(float degrees, const Vec3& axis, const FileLoc& loc) {
    if (length_squared(axis) == 0.f) throw_input_error(loc, "Rotate: the axis is zero");
    concat(Transform::rotate(degrees, axis));
}

void SceneBuilder::look_at(const Vec3& eye, const Vec3& look, const Vec3& up, const FileLoc& loc) {
    bool ok = true;
    Transform t = Transform::look_at(eye, look, up, &ok);
    if (!ok)
        throw_input_error(loc,
                          "LookAt: the eye equals the target or the up vector is parallel "
                          "to the view direction");
    concat(t);
}

void SceneBuilder::set_ctm(const Transform& t) {
    for (int i = 0; i < 2; ++i)
        if (m_state.active_transforms & (1 << i)) m_state.ctm[i] = t;
}

void SceneBuilder::concat(const Transform& t) {
    for (int i = 0; i < 2; ++i)
        if (m_state.active_transforms & (1 << i)) m_state.ctm[i] = m_state.ctm[i] * t;
}

bool SceneBuilder::ctm_animated() const {
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            if (m_state.ctm[0].m(r, c) != m_state.ctm[1].m(r, c)) return true;
    return false;
}

void SceneBuilder::active_transform(const std::string& which, const FileLoc& loc) {
    if (which == "StartTime")
        m_state.active_transforms = kStartTransform;
    else if (which == "EndTime")
        m_state.active_transforms = kEndTransform;
    else if (which == "All")
        m_state.active_transforms = kAllTransforms;
    else
        throw_input_error(loc, "ActiveTransform \"{}\": expected StartTime, EndTime or All", which);
}

void SceneBuilder::transform_times(double start, double end, const FileLoc& loc) {
    if (!std::isfinite(start) || !std::isfinite(end) || !(end > start))
        throw_input_error(loc,
                          "TransformTimes {} {}: the end time must be greater than the start time",
                          start, end);
    m_desc.transform_start_time = float(start);
    m_desc.transform_end_time = float(end);
}

namespace {

Transform transposed(const double m[16], const FileLoc& loc) {
    float t[4][4];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) t[r][c] = float(m[c * 4 + r]);
    bool ok = true;
    Transform x = Transform::from_matrix(t, &ok);
    if (!ok) throw_input_error(loc, "the matrix is singular or not finite");
    return x;
}

}  // namespace

void SceneBuilder::transform(const double m[16], const FileLoc& loc) {
    set_ctm(transposed(m, loc));
}

void SceneBuilder::concat_transform(const double m[16], const FileLoc& loc) {
    concat(transposed(m, loc));
}

void SceneBuilder::coord_sys_transform(const std::string& name, const FileLoc& loc) {
    auto it = m_named_frames.find(name);
    if (it == m_named_frames.end())
        throw_input_error(loc, "unknown coordinate system \"{}\"", name);
    m_state.ctm[0] = it->second[0];
    m_state.ctm[1] = it->second[1];
}

void SceneBuilder::begin_scope(ScopeKind kind, const FileLoc& loc) {
    m_scopes.push_back(Scope{kind, m_state, loc});
}

namespace {

const char* scope_name(ScopeKind k) {
    switch (k) {
        case ScopeKind::Attribute:
            return "AttributeBegin";
        case ScopeKind::Transform:
            return "TransformBegin";
        case ScopeKind::Object:
            return "ObjectBegin";
    }
    return "";
}

const char* scope_end_name(ScopeKind k) {
    switch (k) {
        case ScopeKind::Attribute:
            return "AttributeEnd";
        case ScopeKind::Transform:
            return "TransformEnd";
        case ScopeKind::Object:
            return "ObjectEnd";
    }
    return "";
}

}  // namespace

void SceneBuilder::end_scope(ScopeKind kind, const FileLoc& loc) {
    if (m_scopes.empty())
        throw_input_error(loc, "{} without a matching {}", scope_end_name(kind), scope_name(kind));
    const Scope& top = m_scopes.back();
    if (top.kind != kind)
        throw_input_error(loc, "{} closes the {} opened at {}", scope_end_name(kind),
                          scope_name(top.kind), top.loc.to_string());
    if (kind == ScopeKind::Transform) {
        m_state.ctm[0] = top.saved.ctm[0];
        m_state.ctm[1] = top.saved.ctm[1];
        m_state.active_transforms = top.saved.active_transforms;
    } else {
        m_state = top.saved;
    }
    m_scopes.pop_back();
}

void SceneBuilder::object_begin(const std::string& name, const FileLoc& loc) {
    if (m_current_object)
        throw_input_error(loc, "ObjectBegin \"{}\" inside the definition of \"{}\"", name,
                          m_current_object_name);
    if (m_objects.count(name)) throw_input_error(loc, "object \"{}\" redefined", name);
    begin_scope(ScopeKind::Object, loc);
    m_current_object = &m_objects[name];
    m_current_object->loc = loc;
    m_current_object_name = name;
}

void SceneBuilder::object_end(const FileLoc& loc) {
    if (!m_current_object) throw_input_error(loc, "ObjectEnd without a matching ObjectBegin");
    end_scope(ScopeKind::Object, loc);
    m_current_object = nullptr;
}

void SceneBuilder::object_instance(const std::string& name, const FileLoc& loc) {
    if (m_current_object)
        throw_input_error(loc, "ObjectInstance inside the definition of object \"{}\"",
                          m_current_object_name);
    auto it = m_objects.find(name);
    if (it == m_objects.end()) throw_input_error(loc, "undefined object \"{}\"", name);
    // Instances are flattened: each becomes copies of the object's meshes.
    for (const ShapeRecord& s : it->second.shapes) {
        ShapeRecord r = s;
        r.instance[0] = m_state.ctm[0];
        r.instance[1] = m_state.ctm[1];
        r.loc = loc;
        ++m_sources[r.source].uses;
        m_shapes.push_back(std::move(r));
    }
}

void SceneBuilder::world_begin(const FileLoc& loc) {
    if (m_in_world) throw_input_error(loc, "WorldBegin given twice");
    if (!m_scopes.empty())
        throw_input_error(loc, "WorldBegin inside the {} opened at {}",
                          scope_name(m_scopes.back().kind), m_scopes.back().loc.to_string());
    m_in_world = true;
    m_state.ctm[0] = m_state.ctm[1] = Transform();
    m_state.active_transforms = kAllTransforms;
    m_named_frames["world"] = {Transform(), Transform()};
}

void SceneBuilder::option(const std::string& name, const std::string& value, bool quoted,
                          const FileLoc& loc) {
    // pbrt-v4 compares names lower-cased without '_' and '-'; a leading type ("bool x") is
    // accepted as well, as parameter lists write it.
    std::string key;
    for (char c : name.substr(name.find_last_of(" \t") + 1))
        if (c != '_' && c != '-') key += char(std::tolower(static_cast<unsigned char>(c)));
    auto expect_bool = [&] {
        if (quoted || (value != "true" && value != "false"))
            throw_input_error(loc, "Option \"{}\": expected true or false, got {}", name,
                              quoted ? "\"" + value + "\"" : value);
    };
    auto expect_string = [&] {
        if (!quoted) throw_input_error(loc, "Option \"{}\": expected a quoted string", name);
    };
    // Options that do not change the image manylight makes: output-only ones, pbrt-v4's choice
    // of engine and render space, spectral sampling (manylight is RGB), texture filtering
    // (manylight does not filter procedural textures), displacement (refused where it is used).
    if (key == "wavefront" || key == "pixelstats" || key == "disablewavelengthjitter" ||
        key == "disabletexturefiltering") {
        expect_bool();
    } else if (key == "msereferenceimage" || key == "msereferenceout") {
        expect_string();
    } else if (key == "rendercoordsys") {
        expect_string();
        if (value != "camera" && value != "cameraworld" && value != "world")
            throw_input_error(loc,
                              "Option \"{}\": unknown rendering coordinate system \"{}\" "
                              "(camera, cameraworld or world)",
                              name, value);
    } else if (key == "displacementedgescale") {
        double v;
        if (quoted || !parse_number(value, &v))
            throw_input_error(loc, "Option \"{}\": expected a number", name);
    } else if (key == "seed") {
        // Changes the noise only, not the image it converges to; `--seed` sets ours.
        double v;
        if (quoted || !parse_number(value, &v) || v != std::floor(v))
            throw_input_error(loc, "Option \"{}\": expected an integer", name);
    } else if (key == "disablepixeljitter" || key == "forcediffuse") {
        expect_bool();
        if (value == "true")
            throw_input_error(loc,
                              "Option \"{}\" true changes the image and is not supported by "
                              "manylight",
                              name);
    } else {
        throw_input_error(loc, "unknown Option \"{}\"", name);
    }
}

void SceneBuilder::camera(const std::string& name, ParameterList params, const FileLoc& loc) {
    // As pbrt: the CTM is the camera's world-to-camera transform, and "camera" names its frame.
    m_desc.world_to_camera = m_state.ctm[0];
    m_desc.world_to_camera_end = m_state.ctm[1];
    m_named_frames["camera"] = {m_state.ctm[0].inverse(), m_state.ctm[1].inverse()};
    m_camera_medium = m_state.outside_medium;
    m_camera_medium_loc = m_state.medium_loc;
    entity(&SceneDesc::camera, name, std::move(params), loc);
}

void SceneBuilder::entity(SceneEntity SceneDesc::*which, const std::string& name,
                          ParameterList params, const FileLoc& loc) {
    if (which == &SceneDesc::film) {
        // What of pbrt-v4's film manylight cannot do, refused here by name (the renderer reads
        // the rest).
        if (name == "spectral")
            throw_input_error(loc,
                              "the pbrt-v4 film \"spectral\" is not supported by manylight "
                              "(it renders RGB)");
        // A gbuffer film's frame for its geometric channels: manylight writes RGB only.
        if (name == "gbuffer") params.get_string("coordinatesystem", "camera");
    }
    SceneEntity& e = m_desc.*which;
    e.name = name;
    e.params = std::move(params);
    e.loc = loc;
}

void SceneBuilder::attribute(const std::string& target, const ParameterList& params,
                             const FileLoc& loc) {
    if (target != "shape" && target != "light" && target != "material" && target != "texture")
        throw_input_error(loc,
                          "Attribute target \"{}\" is unknown or unsupported (shape, light, "
                          "material, texture)",
                          target);
    ParameterList& list = m_state.attributes[target];
    for (const Param& p : params.params()) {
        // A later Attribute overrides an earlier one of the same name.
        ParameterList kept;
        for (const Param& q : list.params())
            if (q.name != p.name) kept.add(q);
        kept.add(p);
        list = std::move(kept);
    }
}

void SceneBuilder::apply_attributes(const char* target, ParameterList& params) const {
    auto it = m_state.attributes.find(target);
    if (it == m_state.attributes.end()) return;
    for (const Param& a : it->second.params()) {
        if (params.has(a.name)) continue;
        Param p = a;
        p.looked_up = true;
        params.add(std::move(p));
    }
}

void SceneBuilder::material(const std::string& type, const ParameterList& params,
                            const FileLoc& loc) {
    auto m = create_material(type, params, m_desc.textures, loc, m_named_materials, &m_images,
                             m_desc.base_dir);
    params.check_unused();
    m_state.material = m.get();
    m_desc.materials.push_back(std::move(m));
}

void SceneBuilder::make_named_material(const std::string& name, const ParameterList& params,
                                       const FileLoc& loc) {
    // pbrt-v4 rejects a second definition of the same name.
    if (m_named_materials.count(name))
        throw_input_error(loc, "named material \"{}\" redefined", name);
    const Param* type = params.find("type");
    if (!type) throw_input_error(loc, "MakeNamedMaterial \"{}\": \"string type\" is missing", name);
    std::string t = params.get_string("type", "");
    auto m = create_material(t, params, m_desc.textures, loc, m_named_materials, &m_images,
                             m_desc.base_dir);
    params.check_unused();
    m_named_materials[name] = m.get();
    m_desc.materials.push_back(std::move(m));
}

void SceneBuilder::named_material(const std::string& name, const FileLoc& loc) {
    auto it = m_named_materials.find(name);
    if (it == m_named_materials.end())
        throw_input_error(loc, "undefined named material \"{}\"", name);
    m_state.material = it->second;
}

void SceneBuilder::texture(const std::string& name, const std::string& kind, const std::string& cls,
                           const ParameterList& params, const FileLoc& loc) {
    if (kind != "float" && kind != "spectrum")
        throw_input_error(loc, "texture \"{}\": type \"{}\" must be \"float\" or \"spectrum\"",
                          name, kind);
    bool exists = kind == "float" ? m_desc.textures.floats.count(name) != 0
                                  : m_desc.textures.rgbs.count(name) != 0;
    if (exists) throw_input_error(loc, "texture \"{}\" redefined", name);
    create_texture(name, kind, cls, params, m_desc.base_dir, m_desc.textures, m_images, loc,
                   m_state.ctm[0]);
    params.check_unused();
}

const Material* SceneBuilder::default_material(const FileLoc& loc) {
    if (!m_default_material) {
        // pbrt's default: diffuse with reflectance 0.5.
        ParameterList none(loc);
        auto m = create_material("diffuse", none, m_desc.textures, loc);
        m_default_material = m.get();
        m_desc.materials.push_back(std::move(m));
    }
    return m_default_material;
}

namespace {

// A shape's "alpha" from a float texture or a constant.
class TextureAlphaMask final : public AlphaMask {
public:
    TextureAlphaMask(std::shared_ptr<const FloatTexture> tex, bool zero = false)
        : m_tex(std::move(tex)), m_zero(zero) {}
    float eval(const Vec3& p, const Vec2& uv, const Vec3& ng) const override {
        return m_tex->eval({p, uv, ng});
    }
    bool removes_all() const override { return m_zero; }

private:
    std::shared_ptr<const FloatTexture> m_tex;
    bool m_zero;  // a constant alpha of 0 or less
};

}  // namespace

std::shared_ptr<const AlphaMask> SceneBuilder::shape_alpha(const ParameterList& params) const {
    const Param* p = params.find("alpha");
    if (!p) return nullptr;
    std::shared_ptr<const FloatTexture> tex;
    if (p->type == "texture") {
        std::string name = params.get_texture("alpha");
        auto it = m_desc.textures.floats.find(name);
        if (it == m_desc.textures.floats.end())
            throw_input_error(p->loc, "\"alpha\": undefined float texture \"{}\"", name);
        tex = it->second;
    } else {
        // As pbrt-v4: a constant alpha of 1 (or more) is no cut-out at all.
        float a = params.get_float("alpha", 1);
        if (a >= 1) return nullptr;
        // On an emitter, pbrt-v4's invisible light: no ray meets it, it emits in full, and
        // light sampling alone finds it (it becomes a delta light there, without MIS).
        return std::make_shared<TextureAlphaMask>(std::make_shared<ConstantFloatTexture>(a),
                                                  a <= 0);
    }
    return std::make_shared<TextureAlphaMask>(std::move(tex));
}

void SceneBuilder::add_shape(size_t source, std::shared_ptr<const AlphaMask> alpha,
                             const FileLoc& loc) {
    ShapeRecord r{source,
                  {m_state.ctm[0], m_state.ctm[1]},
                  {Transform(), Transform()},
                  m_state.reverse_orientation,
                  m_state.material,
                  m_state.area_light,
                  loc,
                  std::move(alpha),
                  m_state.inside_medium,
                  m_state.outside_medium};
    if (m_current_object) {
        // As pbrt-v4: area lights are ignored inside object instances.
        r.area_light = nullptr;
        m_current_object->shapes.push_back(std::move(r));
    } else {
        ++m_sources[source].uses;
        m_shapes.push_back(std::move(r));
    }
}

void SceneBuilder::shape(const std::string& type, const ParameterList& params, const FileLoc& loc) {
    MeshSource src;
    src.loc = loc;
    if (type == "trianglemesh") {
        src.mesh = make_triangle_mesh(params, loc);
    } else if (type == "bilinearmesh") {
        src.mesh = make_bilinear_mesh(params, loc);
    } else if (type == "sphere") {
        src.mesh = make_sphere(params, loc);
    } else if (type == "disk") {
        src.mesh = make_disk(params, loc);
    } else if (type == "cylinder") {
        src.mesh = make_cylinder(params, loc);
    } else if (type == "plymesh") {
        for (const char* unsupported : {"displacement", "edgelength"})
            if (const Param* p = params.find(unsupported))
                throw_input_error(p->loc, "plymesh: \"{}\" (displacement mapping) is not supported",
                                  unsupported);
        const Param* f = params.find("filename");
        std::string name = params.get_string("filename", "");
        if (!f || name.empty()) throw_input_error(loc, "plymesh: \"string filename\" is required");
        std::filesystem::path path(name);
        if (path.is_relative()) path = std::filesystem::path(m_desc.base_dir) / path;
        src.ply_path = path.lexically_normal().string();
        src.loc = f->loc;
        std::error_code ec;
        if (!std::filesystem::exists(src.ply_path, ec))
            throw_input_error(f->loc, "{}: no such file", src.ply_path);
    } else if (type == "curve") {
        src.mesh = make_curves(params, loc);
        // pbrt-v4 cannot sample points on curves (Curve::Sample is not implemented), so curves
        // cannot emit there either.
        if (m_state.area_light && !m_current_object)
            throw_input_error(loc,
                              "an area light on a curve (AreaLightSource at {}) is not supported "
                              "(pbrt-v4 cannot sample curves either)",
                              m_state.area_light->loc.to_string());
    } else if (type == "loopsubdiv") {
        src.mesh = make_loop_subdiv(params, loc);
    } else {
        throw_input_error(loc, "unknown shape \"{}\"", type);
    }
    auto alpha = shape_alpha(params);
    params.check_unused();
    m_sources.push_back(std::move(src));
    if (!m_sources.back().ply_path.empty()) {
        // Read the file while parsing goes on (textures load meanwhile on this thread).
        MeshSource* s = &m_sources.back();
        m_loads.run([s] {
            try {
                s->mesh = load_ply(s->ply_path, s->loc);
            } catch (...) {
                s->error = std::current_exception();
            }
        });
    }
    add_shape(m_sources.size() - 1, std::move(alpha), loc);
}

void SceneBuilder::light_source(const std::string& type, const ParameterList& params,
                                const FileLoc& loc) {
    // pbrt-v4 warns and uses the start transform; an error here says so instead.
    if (ctm_animated())
        throw_input_error(loc,
                          "LightSource \"{}\" under an animated transform: moving lights are not "
                          "supported (set the light's transform with ActiveTransform All)",
                          type);
    auto light = create_light(type, params, m_state.ctm[0], m_desc.base_dir, loc);
    params.check_unused();
    // Its medium is resolved at the end (pbrt-v4 allows media defined after their use).
    m_light_media.push_back({m_desc.lights.size(), m_state.outside_medium, m_state.medium_loc});
    m_desc.lights.push_back(std::move(light));
}

void SceneBuilder::make_named_medium(const std::string& name, const ParameterList& params,
                                     const FileLoc& loc) {
    if (m_named_media.count(name)) throw_input_error(loc, "medium \"{}\" is defined twice", name);
    if (ctm_animated())
        throw_input_error(loc,
                          "MakeNamedMedium \"{}\" under an animated transform: moving "
                          "media are not supported",
                          name);
    const std::string type = params.get_string("type", "");
    if (type.empty()) throw_input_error(loc, "MakeNamedMedium \"{}\" has no \"string type\"", name);
    auto medium = create_medium(type, params, m_state.ctm[0], m_desc.base_dir, loc);
    params.check_unused();
    m_named_media[name] = medium.get();
    m_desc.media.push_back(std::move(medium));
}

void SceneBuilder::medium_interface(const std::string& inside, const std::string& outside,
                                    const FileLoc& loc) {
    m_state.inside_medium = inside;
    m_state.outside_medium = outside;
    m_state.medium_loc = loc;
}

const Medium* SceneBuilder::find_medium(const std::string& name, const FileLoc& loc) const {
    if (name.empty()) return nullptr;
    auto it = m_named_media.find(name);
    if (it == m_named_media.end())
        throw_input_error(loc, "medium \"{}\" is not defined (no MakeNamedMedium of that name)",
                          name);
    return it->second;
}

void SceneBuilder::area_light_source(const std::string& type, ParameterList params,
                                     const FileLoc& loc) {
    m_state.area_light =
        std::make_shared<AreaLightSpec>(AreaLightSpec{type, std::move(params), loc});
}

SceneDesc SceneBuilder::finish() {
    if (!m_scopes.empty()) {
        const Scope& s = m_scopes.back();
        throw_input_error(s.loc, "{} without a matching {} before the end of the input",
                          scope_name(s.kind), scope_end_name(s.kind));
    }

    // Step 1: the PLY reads started while parsing; report the first failure in file order.
    m_loads.wait();
    for (const MeshSource& s : m_sources)
        if (s.error) std::rethrow_exception(s.error);

    // Shapes of the "interface" material do not scatter: without a medium on either side they
    // mark nothing and are left out, so every ray passes through them, and so is an area light
    // on one (as pbrt-v4 ignores it). Between two media they stay: the volumetric path tracer
    // passes through them into the medium beyond.
    std::erase_if(m_shapes, [](const ShapeRecord& r) {
        return r.material && r.material->type() == "interface" &&
               r.inside_medium == r.outside_medium;
    });

    // Media by name, now that every MakeNamedMedium is known (pbrt-v4 allows them after use).
    m_desc.camera_medium = find_medium(m_camera_medium, m_camera_medium_loc);
    for (const LightMedium& lm : m_light_media) {
        Light& light = *m_desc.lights[lm.light];
        light.medium_outside = light.medium_inside = find_medium(lm.name, lm.loc);
    }
    std::vector<std::pair<const Medium*, const Medium*>> shape_media(m_shapes.size());
    std::vector<bool> has_interior(m_shapes.size(), false);
    std::map<const Material*, const Medium*> interiors;
    for (size_t i = 0; i < m_shapes.size(); ++i) {
        const ShapeRecord& r = m_shapes[i];
        shape_media[i] = {find_medium(r.inside_medium, r.loc),
                          find_medium(r.outside_medium, r.loc)};
        // A material with a medium inside (pbrt-v4's "subsurface") fills its shape with it, one
        // medium per material; the outside stays the MediumInterface's.
        const InteriorMedium* in = r.material ? r.material->interior_medium() : nullptr;
        if (!in) continue;
        auto [it, added] = interiors.try_emplace(r.material, nullptr);
        if (added) {
            m_desc.media.push_back(make_homogeneous_medium(in->sigma_a, in->sigma_s, in->g));
            it->second = m_desc.media.back().get();
        }
        shape_media[i].first = it->second;
        has_interior[i] = true;
    }

    // Shapes with no material get the default one, created only when needed.
    for (ShapeRecord& r : m_shapes)
        if (!r.material) r.material = default_material(m_sources[r.source].loc);

    // Moving shapes: the world transform at each time step of the mesh's motion. pbrt-v4 does
    // not support area lights on them, nor do we.
    const float t0 = m_desc.transform_start_time, t1 = m_desc.transform_end_time;
    std::vector<std::vector<Transform>> motion(m_shapes.size());
    for (size_t i = 0; i < m_shapes.size(); ++i) {
        const ShapeRecord& r = m_shapes[i];
        AnimatedTransform obj(r.to_world[0], t0, r.to_world[1], t1);
        AnimatedTransform inst(r.instance[0], t0, r.instance[1], t1);
        if (!obj.is_animated() && !inst.is_animated()) continue;
        if (r.area_light)
            throw_input_error(r.loc,
                              "a shape under an animated transform cannot be an area light "
                              "(AreaLightSource at {}); pbrt-v4 does not support moving area "
                              "lights either",
                              r.area_light->loc.to_string());
        int steps = motion_segments(obj.rotation_angle() + inst.rotation_angle());
        for (int k = 0; k <= steps; ++k) {
            float t = lerp(float(k) / float(steps), t0, t1);
            motion[i].push_back(inst.at(t) * obj.at(t));
        }
    }

    // Step 2: world-space meshes. A source used once is moved, an instanced one copied.
    m_desc.meshes.resize(m_shapes.size());
    parallel_for(size_t(0), m_shapes.size(), [&](size_t i) {
        const ShapeRecord& r = m_shapes[i];
        MeshSource& s = m_sources[r.source];
        auto mesh = s.uses == 1 ? std::move(s.mesh) : std::make_unique<TriangleMesh>(*s.mesh);
        if (!motion[i].empty())
            transform_mesh_motion(*mesh, motion[i], r.reverse_orientation);
        else
            transform_mesh(*mesh, r.instance[0] * r.to_world[0], r.reverse_orientation);
        mesh->material = r.material;
        mesh->alpha = r.alpha;
        // As pbrt-v4: only a shape between two different media changes a ray's medium.
        if (r.inside_medium != r.outside_medium || has_interior[i]) {
            mesh->medium_interface = true;
            mesh->medium_inside = shape_media[i].first;
            mesh->medium_outside = shape_media[i].second;
        }
        m_desc.meshes[i] = std::move(mesh);
    });

    // Step 3: area lights, on the finished world meshes, in file order.
    for (size_t i = 0; i < m_shapes.size(); ++i) {
        const ShapeRecord& r = m_shapes[i];
        if (!r.area_light) continue;
        ParameterList params = r.area_light->params;  // fresh used-flags for each shape
        auto light = create_area_light(r.area_light->type, params, m_desc.meshes[i].get(),
                                       r.area_light->loc, m_desc.base_dir);
        params.check_unused();
        m_desc.meshes[i]->area_light = light.get();
        light->medium_inside = shape_media[i].first;
        light->medium_outside = shape_media[i].second;
        m_desc.lights.push_back(std::move(light));
    }
    return std::move(m_desc);
}

}  // namespace ml
