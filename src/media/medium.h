// Participating media (pbrt-v4's MakeNamedMedium): what fills the space between surfaces, its
// absorption, scattering and emission at each point, a bound on its extinction along a ray
// (the majorant that delta and ratio tracking sample against), and the Henyey-Greenstein phase
// function that scatters light at a point inside it.
#pragma once

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/error.h"
#include "core/math.h"
#include "core/params.h"

namespace ml {

// The Henyey-Greenstein phase function with asymmetry g in (-1, 1), in pbrt-v4's convention:
// wo points back along the ray that arrived and wi away from the point, so that forward
// scattering (g > 0) favours wi near -wo. The density is over solid angle and is also the value
// (a phase function integrates to 1).
float hg_phase(const Vec3& wo, const Vec3& wi, float g);
// A direction wi drawn with density hg_phase(wo, wi, g) over solid angle.
Vec3 sample_hg_phase(const Vec3& wo, float g, const Vec2& u);

// A medium's coefficients at a point, per unit length (world space).
struct MediumProperties {
    RGB sigma_a, sigma_s;
    RGB Le;  // emitted radiance (absorbed light is emitted in proportion to sigma_a)
};

// A stretch of a ray where the medium may be present, with a bound of its extinction there.
struct MajorantSegment {
    float t0 = 0, t1 = 0;  // in units of the ray's parameter
    float sigma_maj = 0;   // >= every channel of sigma_a + sigma_s, per unit of ray parameter
};

// A bound of a medium's extinction over each cell of an nx x ny x nz grid on the unit cube of
// its box (pbrt-v4's majorant grid): delta and ratio tracking take steps sized by the bound of
// the cell they are in, so that empty and thin parts of a medium cost few lookups.
class MajorantGrid {
public:
    MajorantGrid() = default;
    // bound(lo, hi): a bound of the extinction over the box [lo, hi] of the unit cube.
    template <class Bound>
    MajorantGrid(int res, const Bound& bound) : m_res(res) {
        m_v.resize(size_t(res) * size_t(res) * size_t(res));
        const float inv = 1.f / float(res);
        for (int z = 0; z < res; ++z)
            for (int y = 0; y < res; ++y)
                for (int x = 0; x < res; ++x)
                    m_v[index(x, y, z)] =
                        bound(Vec3(float(x) * inv, float(y) * inv, float(z) * inv),
                              Vec3(float(x + 1) * inv, float(y + 1) * inv, float(z + 1) * inv));
    }
    bool empty() const { return m_v.empty(); }
    int res() const { return m_res; }
    float at(int x, int y, int z) const { return m_v[index(x, y, z)]; }

private:
    size_t index(int x, int y, int z) const {
        return (size_t(z) * size_t(m_res) + size_t(y)) * size_t(m_res) + size_t(x);
    }
    int m_res = 0;
    std::vector<float> m_v;
};

// The cells per axis of a majorant grid over data `cells` wide (the most along an axis): two
// cells of data per majorant cell, at most `most` (finer cells cost more steps than they save).
inline int majorant_res(int cells, int most) { return std::clamp((cells + 1) / 2, 1, most); }

// The majorant segments of a ray through a medium, front to back, adjoining: one segment, or the
// cells of a MajorantGrid that the ray crosses (a 3D DDA).
class MajorantIterator {
public:
    MajorantIterator() = default;  // no segment: the ray misses the medium
    explicit MajorantIterator(const MajorantSegment& s) : m_t(s.t0), m_t1(s.t1), m_single(s) {}
    // The grid's cells along o + t d (unit-cube coordinates of the grid) for t in [t0, t1).
    MajorantIterator(const MajorantGrid& grid, const Vec3& o, const Vec3& d, float t0, float t1);
    std::optional<MajorantSegment> next();

private:
    float m_t = 0, m_t1 = 0;
    std::optional<MajorantSegment> m_single;
    const MajorantGrid* m_grid = nullptr;
    int m_voxel[3] = {}, m_step[3] = {}, m_limit[3] = {};
    float m_next_t[3] = {}, m_delta_t[3] = {};
};

class Medium {
public:
    virtual ~Medium() = default;
    // The coefficients at world point p.
    virtual MediumProperties at(const Vec3& p) const = 0;
    // The part of the ray in [0, tmax) where the medium may be non-zero, with a majorant of its
    // extinction per unit of the ray's parameter (the ray's direction need not be unit);
    // nullopt where the ray misses the medium.
    virtual std::optional<MajorantSegment> majorant(const Ray& ray, float tmax) const = 0;
    // The same stretch as adjoining segments, each with its own majorant (at most majorant()'s):
    // what tracking steps through. One segment unless the medium has a MajorantGrid.
    virtual MajorantIterator majorants(const Ray& ray, float tmax) const {
        const std::optional<MajorantSegment> s = majorant(ray, tmax);
        return s ? MajorantIterator(*s) : MajorantIterator();
    }
    // True where the coefficients are the same everywhere (transmittance in closed form).
    virtual bool homogeneous() const = 0;
    float g() const { return m_g; }
    bool emits() const { return m_emits; }
    virtual std::string type() const = 0;

protected:
    float m_g = 0;
    bool m_emits = false;
};

// `MakeNamedMedium name "string type" [ ... ]`: "homogeneous" (or a "preset"), "uniformgrid",
// "rgbgrid", "cloud" or "nanovdb" (its file relative to `base_dir`), the CTM at the directive
// being medium space to world.
std::unique_ptr<Medium> create_medium(const std::string& type, const ParameterList& params,
                                      const Transform& medium_to_world, const std::string& base_dir,
                                      const FileLoc& loc);

// pbrt-v4's emission by temperature: blackbody_radiance_rgb((T - offset) * scale), none at 100 K
// or below, tabulated every 10 K over the range the given raw temperatures reach, up to 100000 K
// (evaluated directly above).
class BlackbodyTable {
public:
    BlackbodyTable() = default;
    BlackbodyTable(float offset, float scale, float raw_min, float raw_max);
    RGB at(float raw) const;
    bool empty() const { return m_rgb.empty(); }

private:
    static constexpr float kTableTop = 1e5f;
    float m_offset = 0, m_scale = 1;
    std::vector<RGB> m_rgb;  // at 100 K, 110 K, ...
};

// The part of `ray` in [0, tmax) inside the box [p0, p1] of medium space, with one majorant for
// all of it; nullopt where it misses the box.
std::optional<MajorantSegment> box_majorant(const Transform& world_to_medium, const Vec3& p0,
                                            const Vec3& p1, float sigma_maj, const Ray& ray,
                                            float tmax);

// The same stretch through the cells of `grid` over the box (one segment where it is empty).
MajorantIterator box_majorants(const Transform& world_to_medium, const Vec3& p0, const Vec3& p1,
                               const MajorantGrid& grid, float sigma_maj, const Ray& ray,
                               float tmax);

// A homogeneous medium of these coefficients (per unit of world distance), without emission.
std::unique_ptr<Medium> make_homogeneous_medium(const RGB& sigma_a, const RGB& sigma_s, float g);

}  // namespace ml
