#include "integrators/registry.h"

#include "integrators/bdlightcuts/bdlightcuts.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/direct/direct.h"
#include "integrators/igi/igi.h"
#include "integrators/lightcuts/lightcuts.h"
#include "integrators/lighttracer/lighttracer.h"
#include "integrators/mdlightcuts/mdlightcuts.h"
#include "integrators/mlt/mlt.h"
#include "integrators/path/path.h"
#include "integrators/pssmlt/pssmlt.h"
#include "integrators/stochasticlightcuts/stochastic_lightcuts.h"
#include "integrators/vpl/vpl.h"
#include "integrators/whitted/whitted.h"

namespace ml {

namespace {

template <typename T>
std::unique_ptr<Integrator> make(const Settings& s) {
    return std::make_unique<T>(s);
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_registry() {
    static const std::vector<IntegratorInfo> table = {
        {"path", "path tracing, NEE + MIS: the unbiased reference", make<PathIntegrator>},
        {"direct", "distribution ray tracing: direct light, soft shadows, glossy reflection",
         make<DirectIntegrator>},
        {"whitted", "Whitted ray tracing: mirrors, glass and direct light",
         make<WhittedIntegrator>},
        {"lighttracer",
         "light tracing: paths from the lights, each vertex splatted through the lens",
         make<LightTracerIntegrator>, true, true},
        {"bdpt", "bidirectional path tracing: every (s, t) strategy, power-heuristic MIS",
         make<BdptIntegrator>, true, true},
        {"mlt",
         "Metropolis light transport in path space (Veach): bidirectional mutations, lens and "
         "caustic perturbations",
         [](const Settings& s) { return std::make_unique<MltIntegrator>(s, false); }, true, true},
        {"cmlt", "coherent MLT: mlt with multiple-try lens perturbations traced as Embree packets",
         [](const Settings& s) { return std::make_unique<MltIntegrator>(s, true); }, true},
        {"pssmlt",
         "primary-sample-space MLT (Kelemen): Metropolis chains over BDPT's paths of one depth",
         make<PssmltIntegrator>, true, true},
        {"vpl", "instant radiosity: every point light and VPL summed with a shadow ray",
         make<VplIntegrator>},
        {"lightcuts", "Lightcuts: the vpl integrator's lights clustered, error-bounded cuts",
         make<LightcutsIntegrator>},
        {"stochasticlightcuts",
         "stochastic Lightcuts (Yuksel 2019): lightcuts' cut, then one light per cluster drawn by "
         "importance: unbiased, no error threshold",
         make<StochasticLightcutsIntegrator>},
        {"mdlightcuts",
         "multidimensional Lightcuts: one cut through the product of a pixel's gather points and "
         "the light tree",
         make<MdLightcutsIntegrator>},
        {"bdlightcuts",
         "bidirectional Lightcuts: eye-path VSPs joined to VPLs at every split, weighted, by one "
         "product cut",
         make<BdLightcutsIntegrator>},
        {"igi",
         "instant global illumination, interleaved: each of n x m sub-buffers shaded by its own "
         "share of the VPLs, blurred over continuous regions (the viewer's moving frames)",
         make<IgiIntegrator>},
    };
    return table;
}

std::string resolve_integrator_alias(const std::string& name) {
    return name == kManyLightAlias ? kRecommendedManyLight : name;
}

std::vector<std::string> integrator_names() {
    std::vector<std::string> names;
    for (const IntegratorInfo& info : integrator_registry()) names.push_back(info.name);
    names.push_back(kManyLightAlias);
    return names;
}

const IntegratorInfo* find_integrator(const std::string& name) {
    const std::string resolved = resolve_integrator_alias(name);
    for (const IntegratorInfo& info : integrator_registry())
        if (info.name == resolved) return &info;
    return nullptr;
}

std::vector<SettingDefault> integrator_settings(
    const IntegratorInfo& info, const std::map<std::string, std::string>& overrides) {
    std::vector<SettingDefault> out;
    Settings settings(info.name, nullptr, overrides);
    settings.record_defaults(&out);
    info.create(settings);
    settings.check_unused();
    return out;
}

std::string integrator_for_pbrt_name(const std::string& pbrt_name) {
    if (pbrt_name == "volpath") return "path";
    // pbrt-v4's "mlt" is Kelemen's primary-sample-space MLT over BDPT, our pssmlt; ours named
    // mlt (Veach's, in path space) is there for --integrator mlt.
    if (pbrt_name == "mlt") return "pssmlt";
    if (find_integrator(pbrt_name)) return pbrt_name;
    return "";
}

}  // namespace ml
