// pbrt-v4's "measured" material: an isotropic or anisotropic BRDF tabulated in the RGL
// database's parameterisation (Dupuy and Jakob 2018), read from its .bsdf tensor file.
//
// The file holds the microfacet distribution (ndf), the projected area (sigma), warps of the
// visible normals (vndf) and of the luminance, and spectra over those warps' domain. The value is
// f = spectrum(u) D(wm) / (4 sigma(wo) cos wi), with u the point of the luminance warp's domain
// that the visible-normal warp maps to wm; sampling runs the two warps forward. manylight turns
// the spectra into linear sRGB once, at load, as a reflectance under D65 (the white of sRGB and
// of pbrt-v4's RGB lights), integrating the spectra as pbrt-v4 interpolates them between the
// file's wavelengths.
#pragma once

#include <memory>
#include <string>

#include "core/error.h"
#include "materials/bsdf.h"
#include "materials/materials.h"
#include "sampling/piecewise_linear_2d.h"

namespace ml {

struct MeasuredBrdf {
    PiecewiseLinear2D ndf, sigma;       // plain tables over (theta, phi) in the unit square
    PiecewiseLinear2D vndf, luminance;  // densities, over (phi_i, theta_i)
    PiecewiseLinear2D rgb[3];           // the spectra as linear sRGB, over (phi_i, theta_i)
    bool isotropic = true;
};

// Reads and checks a .bsdf file; errors name `loc` and the file.
std::shared_ptr<const MeasuredBrdf> load_measured_brdf(const std::string& path, const FileLoc& loc);

class MeasuredBxdf final : public Bxdf {
public:
    explicit MeasuredBxdf(const MeasuredBrdf* brdf) : m_brdf(brdf) {}
    uint8_t flags() const override { return kBxdfGlossyReflection; }
    RGB eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    std::optional<BsdfSample> sample(const Vec3& wo, float uc, const Vec2& u,
                                     TransportMode mode) const override;
    float pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
    // f |cos wi| = spectrum D / (4 sigma(wo)): the tables' largest spectrum and D over sigma(wo).
    RGB max_value_bound(const Vec3& wo, const DirectionCone& cone) const override;

private:
    const MeasuredBrdf* m_brdf;
};

class MeasuredMaterial final : public MaterialBase {
public:
    MeasuredMaterial(std::shared_ptr<const MeasuredBrdf> brdf,
                     std::shared_ptr<FloatTexture> displacement)
        : MaterialBase(std::move(displacement)), m_brdf(std::move(brdf)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "measured"; }

private:
    std::shared_ptr<const MeasuredBrdf> m_brdf;
};

}  // namespace ml
