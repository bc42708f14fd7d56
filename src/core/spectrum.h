// Spectra turned into linear sRGB the way pbrt-v4's RGB film sees them: integrated over
// 360-830 nm (per nm) against the CIE 1931 matching functions (Wyman et al. 2013 fits).
#pragma once

#include <functional>

#include "core/color.h"

namespace ml {

// An emission spectrum (radiance per nm): a flat spectrum of 1 has Y = 106.9.
RGB emission_srgb(const std::function<double(double)>& spectrum);

// A reflectance spectrum (values per wavelength in nm) lit by CIE illuminant D65, the white of
// sRGB and of pbrt-v4's RGB lights: the colour it gives white light, each channel normalised so
// that a reflectance of 1 everywhere is exactly (1, 1, 1).
RGB reflectance_srgb(const std::function<double(double)>& reflectance);

}  // namespace ml
