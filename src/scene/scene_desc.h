// What the pbrt-v4 parser produces: world-space meshes with their materials and area lights,
// the other lights, and the header directives (camera, film, sampler, filter, integrator) as
// parameter lists for the renderer to consume (and to override from the command line).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/animated_transform.h"
#include "core/params.h"
#include "geometry/mesh.h"
#include "lights/light.h"
#include "materials/material.h"
#include "materials/texture.h"
#include "media/medium.h"

namespace ml {

struct SceneEntity {
    std::string name;  // e.g. "perspective", "rgb", "sobol", "gaussian", "path"; empty if absent
    ParameterList params;
    FileLoc loc;
};

struct SceneDesc {
    SceneEntity camera, film, sampler, filter, integrator;
    Transform world_to_camera;      // the CTM at the Camera directive (the start one)
    Transform world_to_camera_end;  // the end CTM there (equal unless the camera moves)
    float transform_start_time = 0, transform_end_time = 1;  // TransformTimes
    // The camera's motion between the transform times.
    AnimatedTransform camera_to_world() const {
        return AnimatedTransform(world_to_camera.inverse(), transform_start_time,
                                 world_to_camera_end.inverse(), transform_end_time);
    }
    std::vector<std::unique_ptr<TriangleMesh>> meshes;
    std::vector<std::unique_ptr<Material>> materials;  // owned; meshes point into them
    std::vector<std::unique_ptr<Light>> lights;        // every light, area lights included
    std::vector<std::unique_ptr<Medium>> media;        // MakeNamedMedium; meshes point into them
    const Medium* camera_medium = nullptr;             // the outside medium at the Camera directive
    NamedTextures textures;
    std::string base_dir;  // directory of the main scene file
};

// Whether light meets a participating medium: the camera's, or one behind a shape's
// MediumInterface.
inline bool has_media(const SceneDesc& desc) {
    if (desc.camera_medium) return true;
    for (const auto& m : desc.meshes)
        if (m->medium_interface) return true;
    return false;
}

// Parses a pbrt-v4 scene file (and what it includes). Throws InputError with file:line:col.
SceneDesc parse_scene_file(const std::string& path);
// Parses scene text held in memory; `name` stands for the file in error messages.
SceneDesc parse_scene_string(const std::string& text, const std::string& base_dir,
                             const std::string& name = "<string>");

}  // namespace ml
