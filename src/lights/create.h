// Factories for `LightSource` and `AreaLightSource` directives.
#pragma once

#include <memory>
#include <string>

#include "core/params.h"
#include "film/image.h"
#include "geometry/mesh.h"
#include "lights/light.h"

namespace ml {

// point, spot, distant, infinite (constant "L" or image "filename", with "scale" and
// "illuminance"/"power" as pbrt-v4 defines them). `light_to_world` is the CTM at the directive.
std::unique_ptr<Light> create_light(const std::string& type, const ParameterList& params,
                                    const Transform& light_to_world, const std::string& base_dir,
                                    const FileLoc& loc);

// `AreaLightSource "diffuse"` ("L" or an image "filename" read relative to base_dir, "scale",
// "twosided", "power") on a world-space mesh whose normals face the emitting side (flip_normals
// already applied).
std::unique_ptr<Light> create_area_light(const std::string& type, const ParameterList& params,
                                         const TriangleMesh* mesh, const FileLoc& loc,
                                         const std::string& base_dir = "");

}  // namespace ml
