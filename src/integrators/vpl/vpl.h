// Instant radiosity, brute force: every point light (the scene's lights turned into point lights,
// plus the VPLs that light paths deposit) shades every gather point with a shadow ray each. It is
// O(lights) per pixel: the exact reference Lightcuts is measured against on the same set.
#pragma once

#include <optional>
#include <string>

#include "integrators/integrator.h"
#include "integrators/settings.h"
#include "manylight/direct.h"
#include "manylight/light_tree.h"
#include "manylight/point_light_set.h"

namespace ml {

// The settings both `vpl` and `lightcuts` read: the point-light set and clamping.
struct ManyLightSettings {
    PointLightOptions lights;
    float clamp = 0;    // > 0: no VPL contributes more than this radiance (per channel)
    int max_depth = 5;  // delta bounces followed from the camera before gathering
    // lights.direct=sample: area and infinite lights by next-event estimation
    // (manylight/direct.h) with lights.direct_samples samples per gather point, not as points.
    int direct_samples = 4;
    // vpl.seed when given; else lights.seed follows the render's seed (use_render_seed).
    std::optional<uint64_t> explicit_seed;
    static ManyLightSettings read(const Settings& s);
    // Sets lights.seed, which every random choice of the point-light set (VPL paths, points on
    // area lights and environment maps) and of the light tree (representatives) draws from:
    // vpl.seed if given, else the render's seed (--seed), so that a new --seed gives new VPLs
    // and representatives. (build_point_light_set hashes it into streams of its own, which never
    // replay the camera's samples.)
    void use_render_seed(uint64_t render_seed);
    // A point light's contribution after clamping (VPLs only; the emitters' lights are exact).
    RGB clamped(const RGB& c, bool is_vpl) const {
        if (clamp <= 0 || !is_vpl) return c;
        return RGB(std::min(c.r, clamp), std::min(c.g, clamp), std::min(c.b, clamp));
    }
};

// What `vpl`, `lightcuts` and `mdlightcuts` shade with: the point-light set and, with
// lights.direct=sample, the sampled direct light.
void build_many_lights(const Scene& scene, const ManyLightSettings& settings, PointLightSet* set,
                       SampledDirectLight* direct);
// For `lightcuts` and `mdlightcuts`: the warning that a fraction `capped` of their cuts (of
// "gather points" or "pixel passes", `what`) stopped at max_cut, where the error is not bounded;
// empty below 10%.
std::string capped_cut_warning(const std::string& integrator, const char* what, double capped,
                               int max_cut, const PointLightSet& set);
// The light tree over `set` as `lightcuts` and `mdlightcuts` build it (representatives seeded by
// lights.seed, the cone weight from the scene's size); *seconds receives the build time.
LightTree build_light_tree(const Scene& scene, const ManyLightSettings& settings,
                           const PointLightSet& set, double* seconds);

class VplIntegrator final : public PixelIntegrator {
public:
    explicit VplIntegrator(const Settings& settings);
    std::string name() const override { return "vpl"; }
    void prepare(const Scene& scene) override;
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;
    RenderResult render(const RenderContext& ctx) override;

private:
    ManyLightSettings m_settings;
    PointLightSet m_set;
    SampledDirectLight m_direct;
};

}  // namespace ml
