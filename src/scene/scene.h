// The scene as rendered: meshes in an Embree scene, the lights (indexed, preprocessed), and the
// parsed description the camera, film and integrator are made from.
#pragma once

#include <memory>
#include <vector>

#include "geometry/embree_scene.h"
#include "scene/scene_desc.h"

namespace ml {

class Scene {
public:
    explicit Scene(SceneDesc desc);

    bool intersect(const Ray& ray, SurfaceInteraction* si) const {
        return m_embree->intersect(ray, si);
    }
    bool intersect_emitter(const Ray& ray, SurfaceInteraction* si) const {
        return m_embree->intersect_emitter(ray, si);
    }
    bool occluded(const Ray& ray) const { return m_embree->occluded(ray); }
    // Packets of four or eight rays (EmbreeScene::intersect4 and the others).
    void intersect4(const Ray rays[4], const bool active[4], SurfaceInteraction si[4],
                    bool hit[4]) const {
        m_embree->intersect4(rays, active, si, hit);
    }
    void intersect8(const Ray rays[8], const bool active[8], SurfaceInteraction si[8],
                    bool hit[8]) const {
        m_embree->intersect8(rays, active, si, hit);
    }
    void occluded4(const Ray rays[4], const bool active[4], bool occluded[4]) const {
        m_embree->occluded4(rays, active, occluded);
    }
    void occluded8(const Ray rays[8], const bool active[8], bool occluded[8]) const {
        m_embree->occluded8(rays, active, occluded);
    }
    // True if nothing blocks the segment from the surface point `si` to the point `p`, which
    // a ray moves by `p_offset` off its own surface (segment_ray; zero: p is on no surface).
    bool visible(const SurfaceInteraction& si, const Vec3& p, const Vec3& p_offset) const {
        return !m_embree->occluded(segment_ray(si.p, si.offset(), p, p_offset, si.time));
    }

    const std::vector<std::unique_ptr<Light>>& lights() const { return m_desc.lights; }
    const std::vector<const Light*>& infinite_lights() const { return m_infinite; }
    Bounds3 bounds() const { return m_bounds; }
    const SceneDesc& desc() const { return m_desc; }
    SceneDesc& desc() { return m_desc; }
    size_t triangle_count() const;
    // Whether any mesh moves while the shutter is open (shapes under ActiveTransform).
    bool moves() const { return m_moves; }
    // Whether any participating medium is reachable: the camera's, or one behind a shape's
    // MediumInterface.
    bool has_media() const { return m_has_media; }
    // Whether, besides, one of the media emits light ("Le").
    bool has_emitting_media() const { return m_has_emitting_media; }
    const Medium* camera_medium() const { return m_desc.camera_medium; }
    // The camera's shutter (render_scene sets it from the camera; pbrt's default [0, 1]): paths
    // that start without a camera ray (VPL paths) draw their time over it, with
    // time_at(u) = lerp(u, open, close), as the camera's rays do.
    void set_shutter(float open, float close) { m_shutter_open = open, m_shutter_close = close; }
    float time_at(float u) const { return lerp(u, m_shutter_open, m_shutter_close); }

private:
    SceneDesc m_desc;
    std::unique_ptr<EmbreeScene> m_embree;
    std::vector<const Light*> m_infinite;
    Bounds3 m_bounds;
    bool m_moves = false;
    bool m_has_media = false, m_has_emitting_media = false;
    float m_shutter_open = 0, m_shutter_close = 1;
};

}  // namespace ml
