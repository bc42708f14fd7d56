// Participating media (pbrt-v4's MakeNamedMedium): what fills the space between surfaces, its
// absorption, scattering and emission at each point, a bound on its extinction along a ray
// (the majorant that delta and ratio tracking sample against), and the Henyey-Greenstein phase
// function that scatters light at a point inside it.
#pragma once

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

class Medium {
public:
    virtual ~Medium() = default;
    // The coefficients at world point p.
    virtual MediumProperties at(const Vec3& p) const = 0;
    // The part of the ray in [0, tmax) where the medium may be non-zero, with a majorant of its
    // extinction per unit of the ray's parameter (the ray's direction need not be unit);
    // nullopt where the ray misses the medium.
    virtual std::optional<MajorantSegment> majorant(const Ray& ray, float tmax) const = 0;
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

// A homogeneous medium of these coefficients (per unit of world distance), without emission.
std::unique_ptr<Medium> make_homogeneous_medium(const RGB& sigma_a, const RGB& sigma_s, float g);

}  // namespace ml
