// pbrt-v4's cameras: "perspective" with a thin lens (fov spans the shorter image axis),
// "orthographic" (thin lens as pbrt-v4 has it), "spherical" (the whole sphere of directions,
// equirectangular or equal-area) and "realistic" (a lens system, camera/lens_system.h, whose rays
// carry a weight: generate_ray's). Camera space looks down +z with +y up and +x to the
// right of the image. Light tracing and BDPT need the camera's importance (We, its pdfs and
// sample_wi): only the perspective camera has it (pbrt-v4's other cameras lack it too).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/aperture.h"
#include "camera/lens_system.h"
#include "core/animated_transform.h"
#include "core/math.h"
#include "core/params.h"

namespace ml {

struct CameraSample {
    Vec2 p_film;     // raster position, pixels, (0,0) at the top-left corner
    Vec2 p_lens;     // [0,1)^2
    float time = 0;  // [0,1): the fraction of the shutter
};

// A point on the lens that sees a given scene point (PerspectiveCamera::sample_wi).
struct CameraWiSample {
    float We = 0;               // importance carried from the lens point towards the scene point
    Vec3 wi;                    // unit direction from the scene point towards the lens point
    float pdf_solid_angle = 0;  // density of wi at the scene point
    Vec3 p_lens, n_lens;        // the lens point and the lens normal (the viewing direction)
    Vec2 p_raster;              // where the scene point lands on the film, pixels
};

enum class Projection { Perspective, Orthographic, Spherical, Realistic };
enum class SphericalMapping { EquiRectangular, EqualArea };

class PerspectiveCamera {
public:
    // Reads "fov", "lensradius", "focaldistance", "frameaspectratio", "screenwindow",
    // "shutteropen", "shutterclose" from `params`. The camera may move (an animated
    // camera-to-world transform, as pbrt-v4's CameraTransform): every query then takes the
    // time, from the ray's time or as an argument.
    // `type` is pbrt-v4's camera name: "perspective", "orthographic", "spherical" (which
    // reads "mapping" too; "fov" is the perspective camera's alone) or "realistic" (which reads
    // "lensfile", relative to `base_dir`, "aperturediameter", "focusdistance", "aperture" and
    // the shutter, and images onto a film `film_diagonal_mm` across). An "aperture" that names
    // an image file is `aperture_file`, which the caller has read (the camera reads no images).
    PerspectiveCamera(const ParameterList& params, const AnimatedTransform& camera_to_world,
                      int width, int height, const std::string& type = "perspective",
                      float film_diagonal_mm = 35.f, const std::string& base_dir = "",
                      ApertureImage aperture_file = {});
    Projection projection() const { return m_projection; }
    // Whether importance(), pdf_we() and sample_wi() exist (the perspective camera's alone).
    bool has_importance() const { return m_projection == Projection::Perspective; }
    // The ray's time is the shutter's at the fraction s.time. `weight` receives the ray's weight
    // (pbrt-v4's CameraRay::weight), by which the radiance along it is multiplied: 1 but for the
    // realistic camera, whose rays are vignetted (0: no ray) and weighted by cos^4; callers
    // that pass none must not meet a realistic camera (has_ray_weights()).
    Ray generate_ray(const CameraSample& s, float* weight = nullptr) const;
    // Whether generate_ray's rays carry weights other than 1 (the realistic camera's).
    bool has_ray_weights() const { return m_projection == Projection::Realistic; }
    // The time at the fraction u of the shutter: how paths without a camera ray (light tracer
    // paths, VPL paths) draw theirs, with the same distribution as generate_ray.
    float sample_time(float u) const { return lerp(u, m_shutter_open, m_shutter_close); }
    float shutter_open() const { return m_shutter_open; }
    float shutter_close() const { return m_shutter_close; }

    // Importance (pbrt-v4's We) of `ray`, leaving a point on the lens (at the ray's time): 1 / (A
    // lens_area cos^4), where A is the area of the image on the plane at unit distance, so that its
    // integral over the film (cos-weighted, over solid angle) and the lens is one. Zero for rays
    // that leave the film; the raster position the ray reaches goes to `p_raster` when not null.
    float importance(const Ray& ray, Vec2* p_raster = nullptr) const;
    // Densities of generate_ray() producing `ray` (raster position uniform over the film):
    // over the lens area, and over solid angle.
    void pdf_we(const Ray& ray, float* pdf_area, float* pdf_solid_angle) const;
    // A lens point towards which `p_ref` sends light (pbrt-v4's SampleWi); nullopt when the
    // point lands off the film or on the lens itself.
    std::optional<CameraWiSample> sample_wi(const Vec3& p_ref, const Vec2& u, float time) const;
    // The viewing direction (the lens normal), world space, at `time`.
    Vec3 forward(float time) const {
        return m_moves ? normalize(m_motion.at(time).vector(Vec3(0, 0, 1))) : m_forward;
    }
    // Area of the lens (1 for a pinhole, whose position is a delta).
    float lens_area() const { return m_lens_radius > 0 ? kPi * sqr(m_lens_radius) : 1.f; }
    // The film that is rendered, pixels: the whole image, or its crop (set_crop).
    int width() const { return m_width; }
    int height() const { return m_height; }
    // Renders only the pixels [x0, x0 + width) x [y0, y0 + height) of the image (pbrt-v4's film
    // pixel bounds): raster positions (CameraSample::p_film, importance's, sample_wi's) are then
    // the crop's, (0, 0) at its top-left corner, and importance is normalised over the crop, so
    // light paths joined to the lens fill the crop as camera samples do.
    void set_crop(int x0, int y0, int width, int height);
    Transform camera_to_world(float time) const {
        return m_moves ? m_motion.at(time) : m_camera_to_world;
    }
    bool moves() const { return m_moves; }
    float lens_radius() const { return m_lens_radius; }
    float focal_distance() const { return m_focal_distance; }
    // How far past the film's edge (pixels, per axis) importance() still sees: a camera sample
    // lands up to the filter's radius less half a pixel outside the film (its pixel's centre
    // plus the filter offset), so light paths joined to the lens must reach as far for the
    // border pixels to get what camera samples give them. 0 by default.
    void set_raster_margin(const Vec2& margin) { m_raster_margin = margin; }
    // The raster position of u in [0, 1)^2 spread over the film and its margin, for samplers
    // that draw raster positions uniformly (Metropolis), and that area over the film's: the
    // weight of a camera ray drawn so, by which its radiance counts as a camera sample's.
    Vec2 raster_point(const Vec2& u) const {
        return Vec2(-m_raster_margin.x + u.x * (float(m_width) + 2 * m_raster_margin.x),
                    -m_raster_margin.y + u.y * (float(m_height) + 2 * m_raster_margin.y));
    }
    // Whether raster position p lies on the film or its margin.
    bool in_raster(const Vec2& p) const {
        return p.x >= -m_raster_margin.x && p.y >= -m_raster_margin.y &&
               p.x < float(m_width) + m_raster_margin.x &&
               p.y < float(m_height) + m_raster_margin.y;
    }
    float raster_area_ratio() const {
        return (float(m_width) + 2 * m_raster_margin.x) *
               (float(m_height) + 2 * m_raster_margin.y) / (float(m_width) * float(m_height));
    }

private:
    // Raster position (the crop's) of a camera-space point on the plane z = 1.
    Vec2 raster_of(const Vec3& p_plane) const;
    // A raster position (the crop's) as a fraction of the whole image.
    Vec2 full_uv(const Vec2& p_film) const;
    // Throws unless has_importance(): light paths cannot reach this camera.
    void require_importance() const;
    // The camera-space ray of each projection, before the camera-to-world transform.
    Ray perspective_ray(const CameraSample& s) const;
    Ray orthographic_ray(const CameraSample& s) const;
    Ray spherical_ray(const CameraSample& s) const;
    // Reads the realistic camera's parameters and builds its lens system.
    void make_lens_system(const ParameterList& params, float film_diagonal_mm,
                          const std::string& base_dir, ApertureImage aperture_file);
    std::shared_ptr<const LensSystem> m_lens;  // the realistic camera's
    Projection m_projection = Projection::Perspective;
    SphericalMapping m_mapping = SphericalMapping::EqualArea;
    Transform world_to_camera(float time) const {
        return m_moves ? m_motion.at(time).inverse() : m_world_to_camera;
    }
    AnimatedTransform m_motion;
    bool m_moves;
    Transform m_camera_to_world, m_world_to_camera;  // at the start
    Vec3 m_forward;
    float m_image_area;               // A: the film's area on the plane z = 1 of camera space
    int m_width, m_height;            // the crop's size (the image's without one)
    int m_full_width, m_full_height;  // the image's
    int m_crop_x = 0, m_crop_y = 0;   // the crop's top-left pixel in the image
    float m_screen[4];                // x min, x max, y min, y max
    float m_tan_half_fov;
    float m_lens_radius, m_focal_distance;
    Vec2 m_raster_margin;
    float m_shutter_open, m_shutter_close;
    FileLoc m_loc;  // the Camera directive's
};

}  // namespace ml
