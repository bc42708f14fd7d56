// The perspective camera with a thin lens (pbrt-v4's "perspective": fov spans the shorter image
// axis; camera space looks down +z with +y up and +x to the right of the image).
#pragma once

#include <memory>

#include "core/math.h"
#include "scene/params.h"

namespace ml {

struct CameraSample {
    Vec2 p_film;     // raster position, pixels, (0,0) at the top-left corner
    Vec2 p_lens;     // [0,1)^2
    float time = 0;  // [0,1)
};

class PerspectiveCamera {
public:
    // Reads "fov", "lensradius", "focaldistance", "frameaspectratio", "screenwindow",
    // "shutteropen", "shutterclose" from `params`.
    PerspectiveCamera(const ParameterList& params, const Transform& camera_to_world, int width,
                      int height);
    Ray generate_ray(const CameraSample& s) const;
    const Transform& camera_to_world() const { return m_camera_to_world; }
    float lens_radius() const { return m_lens_radius; }
    float focal_distance() const { return m_focal_distance; }

private:
    Transform m_camera_to_world;
    int m_width, m_height;
    float m_screen[4];  // x min, x max, y min, y max
    float m_tan_half_fov;
    float m_lens_radius, m_focal_distance;
    float m_shutter_open, m_shutter_close;
};

}  // namespace ml
