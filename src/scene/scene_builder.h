// The meaning of pbrt-v4 directives, apart from their syntax: the graphics state and its scopes,
// named materials, textures and coordinate systems, object instancing, and the shapes and lights
// that become the SceneDesc. The parser (parser.cpp) calls one method per directive.
#pragma once

#include <array>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "materials/create.h"
#include "scene/graphics_state.h"
#include "scene/scene_desc.h"

namespace ml {

class SceneBuilder {
public:
    explicit SceneBuilder(std::string base_dir);
    // Waits for PLY reads still running when parsing stopped at an error.
    ~SceneBuilder();
    SceneBuilder(const SceneBuilder&) = delete;
    SceneBuilder& operator=(const SceneBuilder&) = delete;

    // pbrt-v4 splits a scene into options (before WorldBegin) and the world; each directive
    // belongs to one of them.
    void require_options(const std::string& directive, const FileLoc& loc) const;
    void require_world(const std::string& directive, const FileLoc& loc) const;

    // Transforms: each multiplies the CTM on the right, as pbrt does.
    // Under ActiveTransform StartTime or EndTime they change only that CTM.
    void identity() { set_ctm(Transform()); }
    void translate(const Vec3& d) { concat(Transform::translate(d)); }
    void scale(const Vec3& s) { concat(Transform::scale(s)); }
    void rotate(float degrees, const Vec3& axis, const FileLoc& loc);
    void look_at(const Vec3& eye, const Vec3& look, const Vec3& up, const FileLoc& loc);
    // `m` as written in the file: pbrt stores matrices column by column, so they are transposed.
    void transform(const double m[16], const FileLoc& loc);
    void concat_transform(const double m[16], const FileLoc& loc);
    void coordinate_system(const std::string& name) {
        m_named_frames[name] = {m_state.ctm[0], m_state.ctm[1]};
    }
    void coord_sys_transform(const std::string& name, const FileLoc& loc);
    void reverse_orientation() { m_state.reverse_orientation = !m_state.reverse_orientation; }
    // `ActiveTransform StartTime|EndTime|All`.
    void active_transform(const std::string& which, const FileLoc& loc);
    // `TransformTimes start end` (before WorldBegin): the times of the two CTMs.
    void transform_times(double start, double end, const FileLoc& loc);

    void begin_scope(ScopeKind kind, const FileLoc& loc);
    void end_scope(ScopeKind kind, const FileLoc& loc);
    void object_begin(const std::string& name, const FileLoc& loc);
    void object_end(const FileLoc& loc);
    void object_instance(const std::string& name, const FileLoc& loc);
    void world_begin(const FileLoc& loc);

    // `Option "name" value`: the options that leave the image unchanged are accepted and
    // ignored; the others are refused (manylight has no way to honour them).
    void option(const std::string& name, const std::string& value, bool quoted, const FileLoc& loc);

    // Camera, Film, Sampler, PixelFilter, Integrator: kept for the renderer, unchecked.
    void camera(const std::string& name, ParameterList params, const FileLoc& loc);
    void entity(SceneEntity SceneDesc::*which, const std::string& name, ParameterList params,
                const FileLoc& loc);

    // `Attribute "target" params`, and their use: each directive of that target gets the
    // parameters it does not set itself. pbrt-v4 does not report unused attributes.
    void attribute(const std::string& target, const ParameterList& params, const FileLoc& loc);
    void apply_attributes(const char* target, ParameterList& params) const;

    void material(const std::string& type, const ParameterList& params, const FileLoc& loc);
    void make_named_material(const std::string& name, const ParameterList& params,
                             const FileLoc& loc);
    void named_material(const std::string& name, const FileLoc& loc);
    void texture(const std::string& name, const std::string& kind, const std::string& cls,
                 const ParameterList& params, const FileLoc& loc);
    void shape(const std::string& type, const ParameterList& params, const FileLoc& loc);
    void light_source(const std::string& type, const ParameterList& params, const FileLoc& loc);
    void area_light_source(const std::string& type, ParameterList params, const FileLoc& loc);
    // `MakeNamedMedium name "string type" ...` (the CTM is the medium's space) and
    // `MediumInterface inside [outside]` (one name: both sides).
    void make_named_medium(const std::string& name, const ParameterList& params,
                           const FileLoc& loc);
    void medium_interface(const std::string& inside, const std::string& outside,
                          const FileLoc& loc);

    // Checks that every scope was closed, reads the PLY files (in parallel), moves meshes to
    // world space and creates the area lights. Call once, at the end of the input.
    SceneDesc finish();

private:
    const Material* default_material(const FileLoc& loc);
    void add_shape(size_t source, std::shared_ptr<const AlphaMask> alpha, const FileLoc& loc);
    std::shared_ptr<const AlphaMask> shape_alpha(const ParameterList& params) const;
    void set_ctm(const Transform& t);
    void concat(const Transform& t);
    bool ctm_animated() const;

    SceneDesc m_desc;
    GraphicsState m_state;
    std::vector<Scope> m_scopes;
    bool m_in_world = false;
    std::map<std::string, std::array<Transform, 2>> m_named_frames;
    std::map<std::string, const Material*> m_named_materials;
    std::map<std::string, const Medium*> m_named_media;
    std::string m_camera_medium;  // the outside medium's name at the Camera directive
    FileLoc m_camera_medium_loc;
    // Each LightSource's outside medium by name (Light::medium_outside), resolved at the end.
    struct LightMedium {
        size_t light;
        std::string name;
        FileLoc loc;
    };
    std::vector<LightMedium> m_light_media;
    const Medium* find_medium(const std::string& name, const FileLoc& loc) const;
    const Material* m_default_material = nullptr;
    ImageCache m_images;
    // A deque: PLY reads running in m_loads hold pointers to their sources while more are added.
    std::deque<MeshSource> m_sources;
    TaskGroup m_loads;
    std::vector<ShapeRecord> m_shapes;
    std::map<std::string, ObjectDef> m_objects;
    ObjectDef* m_current_object = nullptr;  // inside ObjectBegin ... ObjectEnd
    std::string m_current_object_name;
};

}  // namespace ml
