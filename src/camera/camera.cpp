#include "camera/camera.h"

#include "sampling/warps.h"

namespace ml {

PerspectiveCamera::PerspectiveCamera(const ParameterList& params, const Transform& camera_to_world,
                                     int width, int height)
    : m_camera_to_world(camera_to_world), m_width(width), m_height(height) {
    float fov = params.get_float("fov", 90.f);
    if (!(fov > 0.f && fov < 180.f))
        throw_input_error(params.find("fov")->loc, "\"fov\" must lie in (0, 180) degrees");
    m_tan_half_fov = std::tan(radians(fov) * 0.5f);
    m_lens_radius = params.get_float("lensradius", 0.f);
    m_focal_distance = params.get_float("focaldistance", 1e6f);
    if (m_lens_radius < 0.f || m_focal_distance <= 0.f)
        throw_input_error(params.loc(), "\"lensradius\" must be >= 0 and \"focaldistance\" > 0");
    float frame = params.get_float("frameaspectratio", float(width) / float(height));
    if (frame > 1.f) {
        m_screen[0] = -frame, m_screen[1] = frame, m_screen[2] = -1.f, m_screen[3] = 1.f;
    } else {
        m_screen[0] = -1.f, m_screen[1] = 1.f, m_screen[2] = -1.f / frame,
        m_screen[3] = 1.f / frame;
    }
    std::vector<float> sw = params.get_floats("screenwindow");
    if (!sw.empty()) {
        if (sw.size() != 4)
            throw_input_error(params.find("screenwindow")->loc, "\"screenwindow\" needs 4 values");
        for (int i = 0; i < 4; ++i) m_screen[i] = sw[i];
    }
    m_shutter_open = params.get_float("shutteropen", 0.f);
    m_shutter_close = params.get_float("shutterclose", 1.f);
}

Ray PerspectiveCamera::generate_ray(const CameraSample& s) const {
    // Raster to screen window to the z = 1 plane of camera space.
    float sx = m_screen[0] + (s.p_film.x / m_width) * (m_screen[1] - m_screen[0]);
    float sy = m_screen[3] - (s.p_film.y / m_height) * (m_screen[3] - m_screen[2]);
    Vec3 dir = normalize(Vec3(sx * m_tan_half_fov, sy * m_tan_half_fov, 1.f));
    Ray ray{Vec3(0, 0, 0), dir};
    if (m_lens_radius > 0.f) {
        // Thin lens: every ray through the lens point meets the pinhole ray at the focal plane.
        Vec2 lens = sample_uniform_disk_concentric(s.p_lens) * m_lens_radius;
        float ft = m_focal_distance / dir.z;
        Vec3 focus = dir * ft;
        ray.o = Vec3(lens.x, lens.y, 0);
        ray.d = normalize(focus - ray.o);
    }
    ray.time = lerp(s.time, m_shutter_open, m_shutter_close);
    ray.o = m_camera_to_world.point(ray.o);
    ray.d = normalize(m_camera_to_world.vector(ray.d));
    return ray;
}

}  // namespace ml
