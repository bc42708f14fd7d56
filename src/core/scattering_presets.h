// pbrt-v4's named scattering coefficients (its GetMediumScatteringProperties): measured media
// from Jensen et al. 2001 and Narasimhan et al. 2006, in mm^-1, for a homogeneous medium's and
// the subsurface material's "preset" / "name".
#pragma once

#include <optional>
#include <string>

#include "core/color.h"

namespace ml {

struct ScatteringPreset {
    RGB sigma_a, sigma_s;  // per mm; sigma_s is the reduced scattering coefficient (use g = 0)
};

// The preset called `name` (pbrt-v4's spelling, e.g. "Skin1", "Regular Milk"), or nullopt.
std::optional<ScatteringPreset> scattering_preset(const std::string& name);
// Every preset's name, comma-separated, for an error message.
std::string scattering_preset_names();

}  // namespace ml
