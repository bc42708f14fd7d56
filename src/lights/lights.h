// Constructors of the concrete lights, already in world space with final emission values (scale,
// power and illuminance applied by create_light / create_area_light). Tests and the Lightcuts
// conversion build lights through these directly.
#pragma once

#include <array>
#include <memory>

#include "core/color.h"
#include "core/math.h"
#include "film/image.h"
#include "geometry/mesh.h"
#include "lights/light.h"

namespace ml {

// Isotropic point light of intensity I at p.
std::unique_ptr<Light> make_point_light(const Vec3& p, const RGB& I);
// Spot light at p along unit `axis`, full intensity inside cos_start, none outside cos_end, a
// smoothstep between (pbrt-v4).
std::unique_ptr<Light> make_spot_light(const Vec3& p, const Vec3& axis, const RGB& I,
                                       float cos_start, float cos_end);
// Goniometric light: intensity I times the nearest value of a res x res equal-area octahedral
// map (row-major, top row first, non-negative) of directions in the space image_to_world maps to
// the world (the light at its origin).
std::unique_ptr<Light> make_goniometric_light(const Transform& image_to_world, const RGB& I,
                                              std::vector<float> values, int res);
// Projection light at light space's origin, projecting `image` (linear, scaled, non-negative)
// along +z with pbrt-v4's framing: fov (degrees) spans the image's shorter side, its top row
// towards light +y.
std::unique_ptr<Light> make_projection_light(const Transform& light_to_world, Image image,
                                             float fov_degrees);
// Distant light arriving along -w (w: unit direction towards the light) with radiance L.
std::unique_ptr<Light> make_distant_light(const Vec3& w, const RGB& L);
// Diffuse emitter over a whole world-space mesh, radiance L leaving the side of
// triangle_normal() (both sides when two_sided). The mesh must outlive the light.
std::unique_ptr<Light> make_diffuse_area_light(const TriangleMesh* mesh, const RGB& L,
                                               bool two_sided);
// The same with radiance from an image (linear, scaled) read at the mesh's texture coordinates
// (u, 1 - v), bilinearly (pbrt-v4's "filename").
std::unique_ptr<Light> make_image_area_light(const TriangleMesh* mesh, Image image, bool two_sided);
// Constant environment radiance L.
std::unique_ptr<Light> make_uniform_infinite_light(const RGB& L);

enum class EnvMapping {
    EqualArea,  // square images: pbrt-v4's equal-area octahedral map, +z (light space) at centre
    LatLong,    // 2:1 images: u = phi / 2pi, v = theta / pi, theta from +z (light space)
};
// Environment map (linear RGB, multiplied by scale) seen through the rotation light_to_world.
std::unique_ptr<Light> make_image_infinite_light(Image image, EnvMapping mapping,
                                                 const Transform& light_to_world, float scale);

// pbrt-v4's portal light: the square equal-area map `image` (linear, scaled) seen through the
// rectangle portal[0..3] (world space, in order around it), only from its side
// cross(portal[3] - portal[0], portal[1] - portal[0]) faces.
std::unique_ptr<Light> make_portal_infinite_light(const Image& image,
                                                  const Transform& light_to_world,
                                                  const std::array<Vec3, 4>& portal);

// Illuminance at a +z-facing (light space) point due to the map's upper hemisphere, by the
// mapping's pixel solid angles; used by "illuminance" for image lights.
float image_upper_hemisphere_illuminance(const Image& image, EnvMapping mapping);

}  // namespace ml
