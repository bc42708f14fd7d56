// Lights. sample_li/pdf_li serve next-event estimation at a shading point (pdfs over solid angle
// at the receiver); sample_le/pdf_le serve paths started at lights (position and direction pdfs
// apart); power() serves power-based light selection.
#pragma once

#include <optional>
#include <vector>

#include "core/color.h"
#include "core/math.h"
#include "geometry/interaction.h"
#include "lights/light_bounds.h"

namespace ml {

struct PointLight;
class Sampler;

enum class LightType {
    DeltaPosition,   // point, spot
    DeltaDirection,  // distant
    Area,            // diffuse emitters on meshes
    Infinite,        // environment (constant or image)
};
inline bool is_delta_light(LightType t) {
    return t == LightType::DeltaPosition || t == LightType::DeltaDirection;
}

struct LightSampleContext {
    Vec3 p;   // receiving point
    Vec3 ng;  // its geometric normal (zero if none)
    Vec3 ns;  // its shading normal (zero if none)
    // The caller also samples the BSDF and weighs the two by MIS, with pdf_li given the same
    // context (pbrt-v4's allowIncompletePDF): a light may then leave out of its density the
    // directions that BSDF sampling covers well (the image infinite light leaves out those
    // darker than its average, a uniform one all), which lowers the variance.
    bool allow_incomplete_pdf = false;
};

struct LightLiSample {
    RGB L;                      // radiance (or, for delta lights, intensity / distance^2)
    Vec3 wi;                    // unit direction from the receiver towards the light
    float pdf_solid_angle = 0;  // for delta lights: 1 (a discrete choice)
    Vec3 p_light;               // point on the light (for infinite/distant: far along wi)
    Vec3 n_light;               // normal there (zero for point-like lights)
    Vec3 p_error;               // error bound of each coordinate of p_light (zero: exact)
    uint32_t prim = 0;          // area lights: the triangle of the mesh p_light is on
    Vec2 uv;                    // area lights: the surface's texture coordinates at p_light
    // What a shadow ray towards p_light moves it by (segment_ray).
    Vec3 offset() const { return surface_offset(n_light, p_error); }
};

struct LightLeSample {
    RGB L;              // emitted radiance along the ray
    Ray ray;            // origin on the light, unit direction
    Vec3 n_light;       // surface normal at the origin (zero for points and directions)
    Vec3 p_error;       // error bound of each coordinate of the origin (zero: exact)
    uint32_t prim = 0;  // area lights: the triangle of the mesh the origin is on
    Vec2 uv;            // area lights: the surface's texture coordinates at the origin
    float pdf_pos = 0;  // area density of the origin (1 for delta positions)
    float pdf_dir = 0;  // solid-angle density of the direction (1 for delta directions)
};

class Medium;

class Light {
public:
    virtual ~Light() = default;
    virtual LightType type() const = 0;
    // Whether rays can meet the light and see its emission (light samples then share it with
    // BSDF samples by MIS): every light but the delta ones and the area lights on shapes of
    // constant alpha 0 (pbrt-v4's invisible lights, which light sampling alone finds).
    virtual bool met_by_rays() const { return !is_delta_light(type()); }

    // Scene-wide set-up once the scene's bounds are known (distant and infinite lights).
    virtual void preprocess(const Bounds3& scene_bounds) {}

    virtual std::optional<LightLiSample> sample_li(const LightSampleContext& ctx,
                                                   const Vec2& u) const = 0;
    // Solid-angle density at ctx of sample_li choosing direction wi that reaches the light at
    // p_light with normal n_light on triangle `prim` of its mesh (area lights); infinite lights
    // use wi alone; delta lights: 0.
    virtual float pdf_li(const LightSampleContext& ctx, const Vec3& wi, const Vec3& p_light,
                         const Vec3& n_light, uint32_t prim) const = 0;

    // Area lights: radiance leaving point p (normal n, texture coords uv) in direction w.
    virtual RGB radiance(const Vec3& p, const Vec3& n, const Vec2& uv, const Vec3& w) const {
        return RGB();
    }
    // Point-like lights whose intensity varies by direction in a way that no PointLight field
    // describes (goniometric, projection): the intensity leaving towards unit world direction w.
    // Their point lights point back here (PointLight::emitter).
    virtual RGB emitted_intensity(const Vec3& w) const { return RGB(); }
    // Infinite lights: radiance arriving along a ray that escapes the scene (portal lights also
    // read its origin: they light only the points that see the sky through the portal).
    virtual RGB radiance_escaped(const Ray& ray) const { return RGB(); }

    virtual std::optional<LightLeSample> sample_le(const Vec2& u_pos, const Vec2& u_dir) const = 0;
    // Densities of sample_le producing `ray` (from a point with normal n_light on the light).
    virtual void pdf_le(const Ray& ray, const Vec3& n_light, float* pdf_pos,
                        float* pdf_dir) const = 0;

    // Lights whose light paths start on a disk as large as the scene's bounding sphere, facing
    // the light (distant and infinite lights): that sphere (the disk's plane touches it on the
    // light's side; sample_le's origins are uniform over the disk). false for the others.
    virtual bool emission_sphere(Vec3* center, float* radius) const { return false; }

    // Total emitted power (flux), RGB.
    virtual RGB power() const = 0;

    // Where and how the light emits, for the light tree (lights with a position: point, spot,
    // area); nullopt for distant and infinite lights, which the tree sampler treats apart.
    virtual std::optional<LightBounds> bounds() const { return std::nullopt; }

    // Appends point lights standing for this light (Lightcuts, DESIGN.md section 2): one for a
    // point, spot or distant light; `n` samples for area lights (two lights per sample when
    // two-sided) and environment lights, stratified with randomness from `sampler`, so that the
    // point lights' emission is an unbiased estimate of the light's. Lights that cannot be
    // turned into point lights append none.
    virtual void to_point_lights(int n, Sampler& sampler, std::vector<PointLight>& out) const {}

    int index = -1;  // position in the scene's light list, set by the scene

    // The participating media the light emits into (pbrt-v4: the MediumInterface current at
    // the LightSource, or the emitting shape's): `medium_outside` on the side its normal faces,
    // `medium_inside` behind it; the same for lights without a surface. Null: no medium.
    const Medium* medium_outside = nullptr;
    const Medium* medium_inside = nullptr;
    // The medium a ray leaving the light in direction w (from a point with normal n; zero for
    // points and directions) starts in.
    const Medium* medium_towards(const Vec3& w, const Vec3& n) const {
        return n == Vec3() || dot(w, n) > 0 ? medium_outside : medium_inside;
    }
};

}  // namespace ml
