// pbrt-v4's "realistic" camera's optics: a stack of spherical lens interfaces and an aperture
// stop, read from a lens table (rows of curvature radius, thickness, index of refraction and
// aperture diameter, in mm; radius 0 is the stop), focused by moving the stack along the axis
// (thick-lens approximation) and sampled through bounds on its exit pupil.
//
// Camera space as pbrt-v4's: the film lies in the plane z = 0, millimetres across (the film's
// "diagonal"), the lens in front of it towards +z, lengths in metres. Rays start on the film,
// aim at a point of the rear element's exit-pupil bounds and are refracted through every
// interface; those stopped by an aperture are lost (weight 0).
#pragma once

#include <string>
#include <vector>

#include "camera/aperture.h"
#include "core/math.h"
#include "core/params.h"

namespace ml {

// An axis-aligned rectangle in the plane of the rear element, metres; empty when lo > hi.
struct PupilBounds {
    Vec2 lo{kInfinity, kInfinity}, hi{-kInfinity, -kInfinity};
    bool empty() const { return !(lo.x < hi.x && lo.y < hi.y); }
    float area() const { return empty() ? 0.f : (hi.x - lo.x) * (hi.y - lo.y); }
    bool inside(const Vec2& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
    }
    void expand(const Vec2& p) {
        lo = Vec2(std::min(lo.x, p.x), std::min(lo.y, p.y));
        hi = Vec2(std::max(hi.x, p.x), std::max(hi.y, p.y));
    }
};

// One camera ray leaving the lens: camera space, and pbrt-v4's weight (0: vignetted).
struct LensRay {
    Ray ray;
    float weight = 0;
};

class LensSystem {
public:
    // The table's rows (4 numbers each, mm), the stop's diameter ("aperturediameter", mm,
    // clamped to the table's), the distance in focus (metres), the film's diagonal (mm) and the
    // image's aspect (height / width). Throws InputError at `loc` for a lens it cannot use.
    LensSystem(const std::vector<float>& table, float aperture_diameter_mm, float focus_distance,
               float film_diagonal_mm, float aspect, ApertureImage aperture, const FileLoc& loc);

    // The ray through raster fraction `s` of the film ([0,1)^2, y down) and a point `u` of the
    // exit-pupil bounds, in camera space, with weight cos^4(theta) / (pdf_area z_rear^2) times
    // the aperture image's value (pbrt-v4's RealisticCamera::GenerateRay).
    LensRay generate(const Vec2& s, const Vec2& u) const;

    // A ray from the film side (camera space) through every interface to the scene side: its
    // weight (the aperture image's value, 1 without one; 0 when it is stopped), `out` the ray.
    float trace_from_film(const Ray& r, Ray* out) const;
    // A ray from the scene side through every interface to the film side: whether it passes.
    bool trace_from_scene(const Ray& r, Ray* out) const;

    float rear_z() const { return m_elements.back().thickness; }
    float front_z() const;
    // The exit-pupil bounds for film points at distance [r0, r1] from the centre along +x.
    PupilBounds bound_exit_pupil(float r0, float r1) const;
    const PupilBounds& pupil_bounds(int i) const { return m_pupil[size_t(i)]; }
    int pupil_bounds_count() const { return int(m_pupil.size()); }

private:
    struct Element {
        float radius;     // curvature radius, metres; 0 for the aperture stop
        float thickness;  // to the next interface towards the film, metres
        float eta;        // index of refraction on the film side; 0 (air) for the stop
        float aperture_radius;
    };
    // The thickness of the last element that focuses the lens at `focus_distance`.
    float focus_thick_lens(float focus_distance, const FileLoc& loc) const;

    std::vector<Element> m_elements;  // from the scene side to the film
    ApertureImage m_aperture;
    float m_film_diagonal;             // metres
    Vec2 m_film_half;                  // half the film's physical extent, metres
    std::vector<PupilBounds> m_pupil;  // per band of film radius
};

// Reads a lens table: numbers separated by anything else, '#' to the end of a line a comment.
// Throws InputError at `loc` when the file cannot be read or holds no multiple of four numbers.
std::vector<float> read_lens_table(const std::string& path, const FileLoc& loc);

}  // namespace ml
