// Small scenes for the point-light and VPL tests: a quad light, and an open box of every kind
// of VPL surface under it.
#pragma once

#include <fmt/format.h>

#include <memory>
#include <string>

#include "manylight/point_light_set.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"

namespace ml::vpl_test {

// A scene file of `world` seen by an 8x8 camera at z = -5 looking at the origin.
inline std::string scene_text(const std::string& world) {
    return R"(LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
)" + world;
}

inline std::unique_ptr<Scene> make_scene(const std::string& world) {
    return std::make_unique<Scene>(parse_scene_string(scene_text(world), "."));
}

// A quad light at y = 1 over [-0.5, 0.5]^2 in x and z, facing down.
inline const char* const kQuadLight = R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1 2 3 ] {}
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -0.5 1 -0.5  0.5 1 -0.5  0.5 1 0.5  -0.5 1 0.5 ]
    "normal N" [ 0 -1 0  0 -1 0  0 -1 0  0 -1 0 ]
AttributeEnd
)";

inline PointLightSet vpls_only(const Scene& scene, int count, int max_depth, uint64_t seed,
                               GlossyVpls glossy = GlossyVpls::Bsdf) {
    PointLightOptions o;
    o.emitters = false;
    o.vpl_count = count;
    o.vpl_max_depth = max_depth;
    o.vpl_glossy = glossy;
    o.seed = seed;
    return build_point_light_set(scene, o);
}

// An open box: rough conductor floor, a rough dielectric pane, coated-diffuse and diffuse walls,
// lit by the quad light; every kind of VPL surface.
inline std::string mixed_box() {
    return fmt::format(fmt::runtime(kQuadLight), "") + R"(
AttributeBegin
  Material "conductor" "float roughness" [ 0.05 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -2 0 -2  -2 0 2  2 0 2  2 0 -2 ]
AttributeEnd
AttributeBegin
  Material "dielectric" "float roughness" [ 0.2 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -2 0 1  2 0 1  2 2 1  -2 2 1 ]
AttributeEnd
AttributeBegin
  Material "coateddiffuse" "float roughness" [ 0.1 ] "rgb reflectance" [ 0.5 0.4 0.3 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -1.5 0 -2  -1.5 0 2  -1.5 2 2  -1.5 2 -2 ]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.7 0.7 0.7 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ 1.5 0 -2  1.5 0 2  1.5 2 2  1.5 2 -2 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -2 0 3  2 0 3  2 2 3  -2 2 3 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -2 1.5 -2  2 1.5 -2  2 1.5 3  -2 1.5 3 ]
AttributeEnd
)";
}

}  // namespace ml::vpl_test
