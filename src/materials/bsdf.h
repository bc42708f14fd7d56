// BSDFs. A Bxdf works in the local shading frame (normal along +z); a Bsdf pairs one with the
// frame of a hit. Values exclude the cosine factor; every pdf is with respect to solid angle.
#pragma once

#include <cstdint>
#include <optional>

#include "core/color.h"
#include "core/cone.h"
#include "core/math.h"

namespace ml {

// Radiance flows from lights to the camera; importance from the camera to lights (light tracing,
// VPL generation). Non-symmetric BSDFs (refraction, shading normals) differ between the two.
enum class TransportMode { Radiance, Importance };

enum BxdfFlags : uint8_t {
    kBxdfNone = 0,
    kBxdfReflection = 1 << 0,
    kBxdfTransmission = 1 << 1,
    kBxdfDiffuse = 1 << 2,
    kBxdfGlossy = 1 << 3,
    kBxdfSpecular = 1 << 4,  // a delta lobe: not evaluable, only sampled
    kBxdfDiffuseReflection = kBxdfDiffuse | kBxdfReflection,
    kBxdfDiffuseTransmission = kBxdfDiffuse | kBxdfTransmission,
    kBxdfGlossyReflection = kBxdfGlossy | kBxdfReflection,
    kBxdfGlossyTransmission = kBxdfGlossy | kBxdfTransmission,
    kBxdfSpecularReflection = kBxdfSpecular | kBxdfReflection,
    kBxdfSpecularTransmission = kBxdfSpecular | kBxdfTransmission,
    kBxdfAll = kBxdfDiffuse | kBxdfGlossy | kBxdfSpecular | kBxdfReflection | kBxdfTransmission
};

struct BsdfSample {
    RGB f;                      // BSDF value (no cosine); for a delta lobe, its weight / |cos|
    Vec3 wi;                    // sampled direction
    float pdf_solid_angle = 0;  // for a delta lobe: the discrete probability of the lobe
    uint8_t flags = kBxdfNone;  // the lobe sampled
    float eta = 1;              // relative IOR crossed (transmission), else 1
    bool is_specular() const { return flags & kBxdfSpecular; }
    bool is_transmission() const { return flags & kBxdfTransmission; }
};

// Local-frame helpers (w in the shading frame).
inline float cos_theta(const Vec3& w) { return w.z; }
inline float abs_cos_theta(const Vec3& w) { return std::abs(w.z); }
inline bool same_hemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0; }

class Bxdf {
public:
    virtual ~Bxdf() = default;
    virtual uint8_t flags() const = 0;
    // f(wo, wi); zero for delta lobes.
    virtual RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const = 0;
    // Samples wi given wo; uc picks among lobes, u places the direction.
    virtual std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                             TransportMode mode) const = 0;
    // Density of sample() over solid angle, excluding delta lobes.
    virtual float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const = 0;
    // Lightcuts' material bound: an upper bound of eval(wo, wi) * |cos wi| over every wi in the
    // cone (Radiance mode). Delta lobes contribute nothing (a point light cannot be hit by one).
    // The default, +infinity, is sound for a Bxdf that knows no better (bxdf_bounds.cpp).
    virtual RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const;
    // The diffuse part of eval: what is left without glossy and specular lobes (a coated
    // surface's base seen through its coat); the whole of a purely diffuse Bxdf, none of a
    // glossy one that does not say otherwise. Glossy VPLs keep only this with vpl.glossy=diffuse.
    virtual RGB eval_diffuse(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
        return (flags() & (kBxdfGlossy | kBxdfSpecular)) ? RGB() : eval(wo, wi, mode);
    }
    // max over wo of eval_diffuse(wo, wi) (Radiance mode), where the Bxdf knows it exactly;
    // nullopt: unknown (callers probe).
    virtual std::optional<RGB> max_diffuse_value(const Vec3& wi) const { return std::nullopt; }
};

// A Bxdf placed at a hit: world-space directions in, world-space directions out.
class Bsdf {
public:
    Bsdf() = default;
    Bsdf(const Frame& shading, const Vec3& ng, const Bxdf* bxdf)
        : m_frame(shading), m_ng(ng), m_bxdf(bxdf) {}
    explicit operator bool() const { return m_bxdf != nullptr; }
    uint8_t flags() const { return m_bxdf ? m_bxdf->flags() : uint8_t(kBxdfNone); }
    bool is_specular_only() const {
        uint8_t f = flags();
        return (f & kBxdfSpecular) && !(f & (kBxdfDiffuse | kBxdfGlossy));
    }
    bool has_nonspecular() const { return flags() & (kBxdfDiffuse | kBxdfGlossy); }
    const Frame& frame() const { return m_frame; }
    const Vec3& ng() const { return m_ng; }
    const Bxdf* bxdf() const { return m_bxdf; }

    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
        Vec3 lo = m_frame.to_local(wo), li = m_frame.to_local(wi);
        if (lo.z == 0) return RGB();
        return m_bxdf->eval(lo, li, mode);
    }
    RGB eval_diffuse(const Vec3& wo, const Vec3& wi,
                     TransportMode mode = TransportMode::Radiance) const {
        Vec3 lo = m_frame.to_local(wo), li = m_frame.to_local(wi);
        if (lo.z == 0) return RGB();
        return m_bxdf->eval_diffuse(lo, li, mode);
    }
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode = TransportMode::Radiance) const {
        Vec3 lo = m_frame.to_local(wo);
        if (lo.z == 0) return std::nullopt;
        auto s = m_bxdf->sample(lo, uc, u, mode);
        if (!s || s->f.is_black() || s->pdf_solid_angle == 0 || s->wi.z == 0) return std::nullopt;
        s->wi = m_frame.to_world(s->wi);
        return s;
    }
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi,
                          TransportMode mode = TransportMode::Radiance) const {
        Vec3 lo = m_frame.to_local(wo), li = m_frame.to_local(wi);
        if (lo.z == 0) return 0;
        return m_bxdf->pdf_solid_angle(lo, li, mode);
    }
    // World-space form of Bxdf::max_value_bound (cone in world space).
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
        Vec3 lo = m_frame.to_local(wo);
        if (lo.z == 0 || cone.is_empty()) return RGB();
        return m_bxdf->max_value_bound(lo, {m_frame.to_local(cone.axis), cone.cos_theta});
    }

private:
    Frame m_frame;
    Vec3 m_ng;
    const Bxdf* m_bxdf = nullptr;
};

}  // namespace ml
