// pbrt-v4's "subsurface" given by "reflectance" and "mfp" instead of "sigma_a" and "sigma_s":
// each channel's single-scattering albedo is the one whose diffuse reflectance, by photon beam
// diffusion (d'Eon and Irving 2011; pbrt-v4's tabulated BSSRDF of a semi-infinite slab under a
// dielectric boundary, Pharr, Jakob and Humphreys, section 11.5), is the given reflectance; the
// extinction is 1 / mfp. manylight then walks that medium (it has no BSSRDF), so the material's
// coefficients are pbrt-v4's, and its image differs from pbrt-v4's by the model alone.
#pragma once

#include <vector>

#include "core/color.h"

namespace ml {

// The diffusion profile's effective albedo as a function of the single-scattering albedo, for
// one phase function asymmetry g and relative index of refraction eta, tabulated as pbrt-v4
// tabulates it (100 albedos, 64 radii, each radius integrated with 100 samples).
class BeamDiffusionTable {
public:
    BeamDiffusionTable(float g, float eta);
    // The effective albedo (diffuse reflectance) of a medium of single-scattering albedo rho.
    float effective_albedo(float rho) const;
    // Its inverse: the single-scattering albedo whose effective albedo is `reflectance`
    // (clamped to the table's range).
    float albedo_for(float reflectance) const;

private:
    std::vector<float> m_rho, m_rho_eff;
};

// Photon beam diffusion's radial profile at distance r (multiple scattering by the dipole over
// depths, plus single scattering), for extinction 1: pbrt-v4's BeamDiffusionMS + BeamDiffusionSS.
float beam_diffusion_profile(float rho, float g, float eta, float r);

// sigma_a and sigma_s of a subsurface material with diffuse `reflectance` (each channel in
// [0, 1]) and mean free path `mfp` (each channel > 0).
void subsurface_from_diffuse(const BeamDiffusionTable& table, const RGB& reflectance,
                             const RGB& mfp, RGB* sigma_a, RGB* sigma_s);

}  // namespace ml
