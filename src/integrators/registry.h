// The one table of integrators: name, what it is good for, and how to make it.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

struct IntegratorInfo {
    std::string name;
    std::string summary;
    std::function<std::unique_ptr<Integrator>(const Settings&)> create;
    // Light paths reach the camera (light tracing, BDPT, Metropolis): the camera must have an
    // importance function (PerspectiveCamera::has_importance).
    bool needs_camera_importance = false;
    // Every strategy that reaches the lens is a splat (light tracing, BDPT): the camera sees
    // points past the film's edge as far as a camera sample's filter offset reaches, so that
    // their splats give the border pixels what camera samples give them
    // (PerspectiveCamera::set_raster_margin). PSSMLT draws its camera rays over the film and
    // that margin; Veach's MLT keeps its paths on the film.
    bool splats_past_film_edge = false;
};

const std::vector<IntegratorInfo>& integrator_registry();
// `--integrator manylight`: the many-light integrator our measurements recommend for a scene
// we know nothing of (bench/RESULTS.md, "Many-light images that converge"). Its settings keep
// the integrator's own names (bdlightcuts.samples).
inline constexpr const char* kManyLightAlias = "manylight";
inline constexpr const char* kRecommendedManyLight = "bdlightcuts";
// `name`, or the integrator the alias `manylight` stands for.
std::string resolve_integrator_alias(const std::string& name);
// The names --integrator takes: the registry's and the alias.
std::vector<std::string> integrator_names();
// Null if no integrator has that name (the alias names the recommended one).
const IntegratorInfo* find_integrator(const std::string& name);
// The settings `info`'s integrator reads, each with its default, in the order it reads them: the
// integrator is made from Settings that record what it asks for (Settings::record_defaults), so
// the defaults are its own code's. A setting read only under another choice (vpl.pilot under
// vpl.sampler=power) is listed when `overrides` (--set's NAME.KEY=VALUE) makes that choice; a
// default that follows another setting (vpl.max_depth: maxdepth - 1) is the one it has when
// nothing is set. Throws UsageError for overrides the integrator does not read.
std::vector<SettingDefault> integrator_settings(
    const IntegratorInfo& info, const std::map<std::string, std::string>& overrides = {});
// Our integrator for a pbrt-v4 `Integrator` name ("volpath" -> "path"), or "" if none.
std::string integrator_for_pbrt_name(const std::string& pbrt_name);

}  // namespace ml
