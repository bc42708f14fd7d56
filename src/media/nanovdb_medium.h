// pbrt-v4's "nanovdb" medium: a density grid read from a NanoVDB file (OpenVDB's compact,
// read-only form, as pbrt-v4 reads it), scaling sigma_a and sigma_s, looked up trilinearly in the
// grid's index space. The one place that includes NanoVDB.
#pragma once

#include <memory>
#include <string>

#include "media/medium.h"

namespace ml {

// `MakeNamedMedium ... "string type" "nanovdb" "string filename" "f.nvdb"`: the float grid named
// "gridname" (default "density"), medium space to world `medium_to_world`; a relative filename is
// read from `base_dir`; a "temperature" grid glows as a blackbody times "Lescale", as pbrt-v4
// makes it.
std::unique_ptr<Medium> create_nanovdb_medium(const ParameterList& params,
                                              const Transform& medium_to_world,
                                              const std::string& base_dir, const FileLoc& loc);

}  // namespace ml
