// A sphere on a diffuse ground plane 400 m across, lit by the sun (a distant light) and the sky
// (a constant infinite light), as pbrt-v4 text at 16x12: where the camera sees a few metres of
// it, nearly every light path from the sun and the sky ends far from what the camera sees.
#pragma once

#include <string>

namespace ml::test {

// `camera`: the LookAt and Camera lines; `lights`: the LightSource lines.
inline std::string sunlit_sphere_scene(const std::string& camera, const std::string& lights) {
    return camera + R"(
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 12 ]
Sampler "independent"
PixelFilter "box"
WorldBegin
)" + lights +
           R"(
Material "diffuse" "rgb reflectance" [ 0.4 0.5 0.6 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -200 0 -200  -200 0 200  200 0 200  200 0 -200 ]
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.8 0.5 0.3 ]
  Translate 0 0.5 0
  Shape "sphere" "float radius" [ 0.5 ]
AttributeEnd
)";
}

}  // namespace ml::test
