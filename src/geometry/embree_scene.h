// Ray queries against all meshes, through Embree 3 (the only file that includes Embree).
#pragma once

#include <memory>
#include <vector>

#include "geometry/interaction.h"
#include "geometry/mesh.h"

namespace ml {

class EmbreeScene {
public:
    // Builds the acceleration structure over the meshes (which must outlive the scene).
    explicit EmbreeScene(const std::vector<const TriangleMesh*>& meshes);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Closest hit along the ray within (0, ray.tmax); fills `si` and returns true on a hit.
    bool intersect(const Ray& ray, SurfaceInteraction* si) const;
    // True if anything blocks the ray within (0, tmax).
    bool occluded(const Ray& ray) const;
    // Closest hits of up to four rays traced together as one Embree packet (coherent rays, such
    // as the neighbouring camera rays of coherent MLT): rays whose `active` is false are not
    // traced. Fills si[i] and hit[i] as intersect() does.
    void intersect4(const Ray rays[4], const bool active[4], SurfaceInteraction si[4],
                    bool hit[4]) const;
    Bounds3 bounds() const { return m_bounds; }

private:
    void fill_interaction(const Ray& ray, unsigned geom_id, unsigned prim_id, float u, float v,
                          float t, const Vec3& ng_embree, SurfaceInteraction* si) const;
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    std::vector<const TriangleMesh*> m_meshes;
    Bounds3 m_bounds;
};

}  // namespace ml
