#include "camera/camera.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "core/assert.h"
#include "sampling/warps.h"

namespace ml {

PerspectiveCamera::PerspectiveCamera(const ParameterList& params,
                                     const AnimatedTransform& camera_to_world, int width,
                                     int height, const std::string& type, float film_diagonal_mm,
                                     const std::string& base_dir, ApertureImage aperture_file)
    : m_motion(camera_to_world),
      m_moves(camera_to_world.is_animated()),
      m_camera_to_world(camera_to_world.start()),
      m_width(width),
      m_height(height),
      m_full_width(width),
      m_full_height(height),
      m_loc(params.loc()) {
    if (type == "perspective") {
        m_projection = Projection::Perspective;
    } else if (type == "orthographic") {
        m_projection = Projection::Orthographic;
    } else if (type == "spherical") {
        m_projection = Projection::Spherical;
        std::string mapping = params.get_string("mapping", "equalarea");
        if (mapping == "equirectangular")
            m_mapping = SphericalMapping::EquiRectangular;
        else if (mapping != "equalarea")
            throw_input_error(params.find("mapping")->loc,
                              "unknown spherical camera mapping \"{}\" (\"equalarea\" or "
                              "\"equirectangular\")",
                              mapping);
    } else if (type == "realistic") {
        m_projection = Projection::Realistic;
    } else {
        throw_input_error(params.loc(),
                          "unsupported camera \"{}\" (perspective, orthographic, spherical and "
                          "realistic are)",
                          type);
    }
    if (m_projection == Projection::Realistic) {
        // pbrt-v4's realistic camera reads none of the projective cameras' parameters.
        make_lens_system(params, film_diagonal_mm, base_dir, std::move(aperture_file));
        m_tan_half_fov = 1, m_lens_radius = 0, m_focal_distance = 1e6f;
        m_screen[0] = m_screen[2] = -1, m_screen[1] = m_screen[3] = 1;
        m_image_area = 4;
        m_shutter_open = params.get_float("shutteropen", 0.f);
        m_shutter_close = params.get_float("shutterclose", 1.f);
        if (!(m_shutter_close >= m_shutter_open))
            throw_input_error(params.loc(),
                              "\"shutterclose\" ({}) must not be less than \"shutteropen\" ({})",
                              m_shutter_close, m_shutter_open);
        m_world_to_camera = m_camera_to_world.inverse();
        m_forward = normalize(m_camera_to_world.vector(Vec3(0, 0, 1)));
        return;
    }
    // The orthographic camera's screen window is in camera-space units at z = 0 (pbrt-v4's
    // Orthographic(0, 1) is the identity on x and y): as a tangent of one, the perspective code
    // below serves both.
    float fov = m_projection == Projection::Perspective ? params.get_float("fov", 90.f) : 90.f;
    if (!(fov > 0.f && fov < 180.f))
        throw_input_error(params.find("fov")->loc, "\"fov\" must lie in (0, 180) degrees");
    m_tan_half_fov = std::tan(radians(fov) * 0.5f);
    m_lens_radius = params.get_float("lensradius", 0.f);
    // pbrt-v4's spherical camera reads and ignores its lens (default focal distance 1e30).
    m_focal_distance =
        params.get_float("focaldistance", m_projection == Projection::Spherical ? 1e30f : 1e6f);
    if (m_projection == Projection::Spherical) m_lens_radius = 0;
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
    if (!(m_shutter_close >= m_shutter_open))
        throw_input_error(params.loc(),
                          "\"shutterclose\" ({}) must not be less than "
                          "\"shutteropen\" ({})",
                          m_shutter_close, m_shutter_open);
    m_world_to_camera = m_camera_to_world.inverse();
    m_forward = normalize(m_camera_to_world.vector(Vec3(0, 0, 1)));
    m_image_area = (m_screen[1] - m_screen[0]) * (m_screen[3] - m_screen[2]) * sqr(m_tan_half_fov);
}

void PerspectiveCamera::set_crop(int x0, int y0, int width, int height) {
    ML_ASSERT(x0 >= 0 && y0 >= 0 && width > 0 && height > 0 && x0 + width <= m_full_width &&
                  y0 + height <= m_full_height,
              "camera crop outside the image");
    // The image area shrinks with the crop: raster to screen is linear, so its share of the
    // pixels is its share of A, and importance stays normalised over the film that is rendered.
    m_image_area *= float(width) * float(height) / (float(m_width) * float(m_height));
    m_crop_x = x0, m_crop_y = y0, m_width = width, m_height = height;
}

Vec2 PerspectiveCamera::full_uv(const Vec2& p_film) const {
    return Vec2((p_film.x + float(m_crop_x)) / float(m_full_width),
                (p_film.y + float(m_crop_y)) / float(m_full_height));
}

Vec2 PerspectiveCamera::raster_of(const Vec3& p) const {
    float sx = p.x / m_tan_half_fov, sy = p.y / m_tan_half_fov;
    return Vec2((sx - m_screen[0]) / (m_screen[1] - m_screen[0]) * m_full_width - float(m_crop_x),
                (m_screen[3] - sy) / (m_screen[3] - m_screen[2]) * m_full_height - float(m_crop_y));
}

void PerspectiveCamera::make_lens_system(const ParameterList& params, float film_diagonal_mm,
                                         const std::string& base_dir, ApertureImage aperture_file) {
    const Param* file = params.find("lensfile");
    std::string name = params.get_string("lensfile", "");
    if (!file || name.empty())
        throw_input_error(params.loc(), "realistic camera: \"string lensfile\" is required");
    std::filesystem::path path(name);
    if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
    std::vector<float> table = read_lens_table(path.lexically_normal().string(), file->loc);
    float aperture_diameter = params.get_float("aperturediameter", 1.f);
    float focus_distance = params.get_float("focusdistance", 10.f);
    if (!(aperture_diameter > 0))
        throw_input_error(params.find("aperturediameter")->loc,
                          "realistic camera: \"aperturediameter\" must be positive");
    if (!(focus_distance > 0))
        throw_input_error(params.find("focusdistance")->loc,
                          "realistic camera: \"focusdistance\" must be positive");
    ApertureImage aperture;
    if (const Param* a = params.find("aperture")) {
        std::string shape = params.get_string("aperture", "");
        if (!shape.empty() && !ApertureImage::is_builtin_name(shape)) {
            if (aperture_file.empty())
                throw_input_error(a->loc, "realistic camera: aperture image \"{}\" was not read",
                                  shape);
            aperture = std::move(aperture_file);
        } else {
            aperture = ApertureImage::builtin(shape);
        }
    }
    if (!(film_diagonal_mm > 0))
        throw_input_error(params.loc(),
                          "realistic camera: the film's \"diagonal\" must be positive");
    m_lens = std::make_shared<const LensSystem>(table, aperture_diameter, focus_distance,
                                                film_diagonal_mm, float(m_height) / float(m_width),
                                                std::move(aperture), params.loc());
}

void PerspectiveCamera::require_importance() const {
    if (!has_importance())
        throw InputError(
            m_loc,
            "the orthographic, spherical and realistic cameras have no importance function: "
            "light paths cannot reach them, so light tracing, BDPT and Metropolis need the "
            "perspective camera");
}

float PerspectiveCamera::importance(const Ray& ray, Vec2* p_raster) const {
    require_importance();
    // In camera space: the ray must leave the lens forwards.
    const Transform w2c = world_to_camera(ray.time);
    Vec3 d = normalize(w2c.vector(ray.d));
    float cos_theta = d.z;
    if (cos_theta <= 0) return 0;
    // The point the ray focuses on, brought back to the plane z = 1 (a pinhole's ray through
    // it leaves the same raster position).
    Vec3 p_plane = d / cos_theta;
    if (m_lens_radius > 0) {
        Vec3 o = w2c.point(ray.o);
        Vec3 p_focus = o + d * ((m_focal_distance - o.z) / cos_theta);
        p_plane = p_focus / m_focal_distance;
    }
    Vec2 r = raster_of(p_plane);
    if (!(r.x >= -m_raster_margin.x && r.x < m_width + m_raster_margin.x &&
          r.y >= -m_raster_margin.y && r.y < m_height + m_raster_margin.y))
        return 0;
    if (p_raster) *p_raster = r;
    float cos2 = cos_theta * cos_theta;
    return 1 / (m_image_area * lens_area() * cos2 * cos2);
}

void PerspectiveCamera::pdf_we(const Ray& ray, float* pdf_area, float* pdf_solid_angle) const {
    require_importance();
    *pdf_area = *pdf_solid_angle = 0;
    if (importance(ray) == 0) return;
    float cos_theta = normalize(world_to_camera(ray.time).vector(ray.d)).z;
    *pdf_area = 1 / lens_area();
    *pdf_solid_angle = 1 / (m_image_area * cos_theta * cos_theta * cos_theta);
}

std::optional<CameraWiSample> PerspectiveCamera::sample_wi(const Vec3& p_ref, const Vec2& u,
                                                           float time) const {
    require_importance();
    // A uniform point on the lens (the pinhole itself when there is no lens).
    Vec2 lens = sample_uniform_disk_concentric(u) * m_lens_radius;
    CameraWiSample s;
    s.p_lens = camera_to_world(time).point(Vec3(lens.x, lens.y, 0));
    s.n_lens = forward(time);
    Vec3 wi = s.p_lens - p_ref;
    float d2 = length_squared(wi);
    if (!(d2 > 0)) return std::nullopt;
    s.wi = wi / std::sqrt(d2);
    float cos_lens = abs_dot(s.n_lens, s.wi);
    if (cos_lens == 0) return std::nullopt;
    s.We = importance(Ray{s.p_lens, -s.wi, kInfinity, time}, &s.p_raster);
    if (s.We == 0) return std::nullopt;
    // Area density 1 / lens_area on the lens, to solid angle at p_ref.
    s.pdf_solid_angle = d2 / (cos_lens * lens_area());
    return s;
}

Ray PerspectiveCamera::generate_ray(const CameraSample& s, float* weight) const {
    Ray ray;
    if (m_projection == Projection::Realistic) {
        if (!weight)
            throw std::logic_error(
                "generate_ray: the realistic camera's rays carry weights the caller must take");
        LensRay lr = m_lens->generate(full_uv(s.p_film), s.p_lens);
        *weight = lr.weight;
        ray = lr.weight > 0 ? lr.ray : Ray{Vec3(0, 0, 0), Vec3(0, 0, 1)};
    } else {
        if (weight) *weight = 1;
        ray = m_projection == Projection::Perspective    ? perspective_ray(s)
              : m_projection == Projection::Orthographic ? orthographic_ray(s)
                                                         : spherical_ray(s);
    }
    ray.time = sample_time(s.time);
    const Transform c2w = camera_to_world(ray.time);
    ray.o = c2w.point(ray.o);
    ray.d = normalize(c2w.vector(ray.d));
    return ray;
}

Ray PerspectiveCamera::perspective_ray(const CameraSample& s) const {
    // Raster to screen window to the z = 1 plane of camera space.
    const Vec2 uv = full_uv(s.p_film);
    float sx = m_screen[0] + uv.x * (m_screen[1] - m_screen[0]);
    float sy = m_screen[3] - uv.y * (m_screen[3] - m_screen[2]);
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
    return ray;
}

Ray PerspectiveCamera::orthographic_ray(const CameraSample& s) const {
    // Raster to the screen window, which is the plane z = 0 of camera space; rays along +z.
    const Vec2 uv = full_uv(s.p_film);
    float sx = m_screen[0] + uv.x * (m_screen[1] - m_screen[0]);
    float sy = m_screen[3] - uv.y * (m_screen[3] - m_screen[2]);
    Ray ray{Vec3(sx, sy, 0), Vec3(0, 0, 1)};
    if (m_lens_radius > 0.f) {
        // pbrt-v4's thin lens, as it is: the ray leaves the lens point around the camera's
        // origin (not around the film point) towards the film point's spot on the focal plane.
        Vec2 lens = sample_uniform_disk_concentric(s.p_lens) * m_lens_radius;
        Vec3 focus = ray.o + ray.d * m_focal_distance;
        ray.o = Vec3(lens.x, lens.y, 0);
        ray.d = normalize(focus - ray.o);
    }
    return ray;
}

Ray PerspectiveCamera::spherical_ray(const CameraSample& s) const {
    // The film is the unit square of the mapping (pbrt-v4's SphericalCamera): equirectangular
    // with theta from +z down and phi around it, or the equal-area octahedral square; then y and
    // z swap, so the top of an equirectangular image looks up (+y).
    const Vec2 uv = full_uv(s.p_film);
    Vec3 dir;
    if (m_mapping == SphericalMapping::EquiRectangular) {
        float theta = kPi * uv.y, phi = 2 * kPi * uv.x;
        dir =
            Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    } else {
        dir = equal_area_square_to_sphere(
            Vec2(std::clamp(uv.x, 0.f, 1.f), std::clamp(uv.y, 0.f, 1.f)));
    }
    std::swap(dir.y, dir.z);
    return Ray{Vec3(0, 0, 0), normalize(dir)};
}

}  // namespace ml
