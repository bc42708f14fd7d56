// The built-in scene rendered when none is given: the Cornell box.
#pragma once

#include <string>

namespace ml {

// pbrt-v4 text of the Cornell box, written from the measurements published by the Cornell
// Program of Computer Graphics (https://www.graphics.cornell.edu/online/box/data.html):
// millimetres, the camera at (278, 273, -800) looking down +z, a 35 mm lens on a 25 mm film.
const std::string& default_scene_text();

}  // namespace ml
