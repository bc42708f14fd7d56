#include "scene/default_scene.h"

namespace ml {

const std::string& default_scene_text() {
    // Reflectances are the usual RGB fits of the measured spectra; the light's radiance is
    // the usual RGB fit of the measured emission spectrum.
    static const std::string text = R"PBRT(# Cornell box (built into manylight)
Integrator "path" "integer maxdepth" [ 16 ]
Sampler "sobol" "integer pixelsamples" [ 64 ]
PixelFilter "gaussian"
Film "rgb" "integer xresolution" [ 400 ] "integer yresolution" [ 400 ]
# The published data are right-handed with the red wall at +x; pbrt cameras are left-handed.
Scale -1 1 1
LookAt 278 273 -800  278 273 0  0 1 0
# 35 mm focal length on a 25 mm square film: 2 atan(12.5 / 35) = 39.3077 degrees.
Camera "perspective" "float fov" [ 39.3077 ]
WorldBegin
MakeNamedMaterial "white" "string type" "diffuse" "rgb reflectance" [ 0.725 0.71 0.68 ]
MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [ 0.63 0.065 0.05 ]
MakeNamedMaterial "green" "string type" "diffuse" "rgb reflectance" [ 0.14 0.45 0.091 ]
NamedMaterial "white"
# floor
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ 552.8 0 0  0 0 0  0 0 559.2  549.6 0 559.2 ]
# ceiling
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ 556 548.8 0  556 548.8 559.2  0 548.8 559.2  0 548.8 0 ]
# back wall
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ 549.6 0 559.2  0 0 559.2  0 548.8 559.2  556 548.8 559.2 ]
# short block
Shape "trianglemesh"
  "integer indices" [ 0 1 2 0 2 3  4 5 6 4 6 7  8 9 10 8 10 11  12 13 14 12 14 15  16 17 18 16 18 19 ]
  "point3 P" [ 130 165 65  82 165 225  240 165 272  290 165 114
               290 0 114  290 165 114  240 165 272  240 0 272
               130 0 65  130 165 65  290 165 114  290 0 114
               82 0 225  82 165 225  130 165 65  130 0 65
               240 0 272  240 165 272  82 165 225  82 0 225 ]
# tall block
Shape "trianglemesh"
  "integer indices" [ 0 1 2 0 2 3  4 5 6 4 6 7  8 9 10 8 10 11  12 13 14 12 14 15  16 17 18 16 18 19 ]
  "point3 P" [ 423 330 247  265 330 296  314 330 456  472 330 406
               423 0 247  423 330 247  472 330 406  472 0 406
               472 0 406  472 330 406  314 330 456  314 0 456
               314 0 456  314 330 456  265 330 296  265 0 296
               265 0 296  265 330 296  423 330 247  423 0 247 ]
NamedMaterial "red"
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ 552.8 0 0  549.6 0 559.2  556 548.8 559.2  556 548.8 0 ]
NamedMaterial "green"
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ 0 0 559.2  0 0 0  0 548.8 0  0 548.8 559.2 ]
# The light, a hair below the ceiling, facing down.
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 17 12 4 ]
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ 343 548.7 227  343 548.7 332  213 548.7 332  213 548.7 227 ]
AttributeEnd
)PBRT";
    return text;
}

}  // namespace ml
