// Ray queries against all meshes, through Embree 3 (the only file that includes Embree).
#pragma once

#include <memory>
#include <vector>

#include "geometry/interaction.h"
#include "geometry/mesh.h"

namespace ml {

class EmbreeScene {
public:
    // Builds the acceleration structure over the meshes (which must outlive the scene). Moving
    // meshes (TriangleMesh::moves) get Embree's motion blur: their steps span the transform
    // times [time_start, time_end]; a ray at time t sees them at the fraction
    // clamp((t - time_start) / (time_end - time_start), 0, 1) of their motion.
    explicit EmbreeScene(const std::vector<const TriangleMesh*>& meshes, float time_start = 0,
                         float time_end = 1);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Closest hit along the ray within (0, ray.tmax); fills `si` and returns true on a hit.
    bool intersect(const Ray& ray, SurfaceInteraction* si) const;
    // The same closest hit, with `si` filled only where the surface hit emits (its mesh has an
    // area light); elsewhere only si->area_light is set (null). For rays that only look for
    // emitters (BSDF samples of the direct light), which skip the interaction's setup.
    bool intersect_emitter(const Ray& ray, SurfaceInteraction* si) const;
    // True if anything blocks the ray within (0, tmax).
    bool occluded(const Ray& ray) const;
    // Packets of four or eight rays traced together (coherent rays, such as the neighbouring
    // tries of coherent MLT), as rtcIntersect4/8 and rtcOccluded4/8: lanes whose `active` is
    // false are not traced and their outputs are left untouched. The active lanes' si[i] and
    // hit[i] are filled as intersect() does, occluded[i] as occluded() answers.
    void intersect4(const Ray rays[4], const bool active[4], SurfaceInteraction si[4],
                    bool hit[4]) const;
    void intersect8(const Ray rays[8], const bool active[8], SurfaceInteraction si[8],
                    bool hit[8]) const;
    void occluded4(const Ray rays[4], const bool active[4], bool occluded[4]) const;
    void occluded8(const Ray rays[8], const bool active[8], bool occluded[8]) const;
    // Over the whole motion.
    Bounds3 bounds() const { return m_bounds; }
    // The fraction of the motion (Embree's time in [0, 1]) at a ray's time.
    float motion_time(float time) const;

private:
    void add_curves(const TriangleMesh& m, unsigned id);
    bool intersect_as(const Ray& ray, SurfaceInteraction* si, bool emitters_only) const;
    template <int N, typename RayHitN>
    void intersect_n(const Ray* rays, const bool* active, SurfaceInteraction* si, bool* hit) const;
    template <int N, typename RayN>
    void occluded_n(const Ray* rays, const bool* active, bool* occluded) const;
    void fill_interaction(const Ray& ray, unsigned geom_id, unsigned prim_id, float u, float v,
                          float t, const Vec3& ng_embree, SurfaceInteraction* si) const;
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    std::vector<const TriangleMesh*> m_meshes;
    Bounds3 m_bounds;
    float m_time_start, m_time_end;
};

}  // namespace ml
