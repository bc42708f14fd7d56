#include "manylight/vpl_budget.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/world.h"
#include "manylight/vpl_sampler.h"
#include "render/integrator.h"

namespace ml {
namespace {

// Appends from's VPLs to `to` as sample_vpls would have made them there.
void append_set(PointLightSet&& from, PointLightSet& to) {
    const auto offset = int32_t(to.surfaces.size());
    for (PointLight pl : from.lights) {
        if (pl.surface >= 0) pl.surface += offset;
        to.lights.push_back(pl);
    }
    to.surfaces.insert(to.surfaces.end(), from.surfaces.begin(), from.surfaces.end());
    for (auto& arena : from.arenas) to.arenas.push_back(std::move(arena));
    to.vpls += from.vpls;
    to.light_paths += from.light_paths;
}

}  // namespace

VplBudget vpl_build_budget(const RenderContext& ctx) {
    VplBudget b;
    if (!(ctx.time_limit > 0)) return b;
    // (At least a trace: 0 would mean no limit.)
    b.seconds = std::max(1e-6, kVplBuildTimeShare * ctx.time_limit - ctx.elapsed());
    b.world = ctx.world;
    return b;
}

int fit_vpl_count(int requested, const VplProbe& smaller, const VplProbe& larger, double seconds) {
    if (larger.count <= 0) return requested;
    double per_vpl = larger.seconds / double(larger.count), fixed = 0;
    if (smaller.count > 0 && larger.count > smaller.count) {
        double slope = (larger.seconds - smaller.seconds) / double(larger.count - smaller.count);
        if (slope > 0 && std::isfinite(slope)) {
            per_vpl = slope;
            fixed = std::max(0.0, larger.seconds - slope * double(larger.count));
        }
    }
    if (!(per_vpl > 0)) return requested;
    const double fits = (seconds - fixed) / per_vpl;
    if (fits >= double(requested)) return requested;
    return std::max(std::min(requested, kVplFirstProbe), int(std::max(0.0, fits)));
}

int sample_vpls_within(const Scene& scene, const PerspectiveCamera* camera,
                       const VplOptions& options, const VplBudget& budget, PointLightSet& set) {
    const int requested = options.count;
    if (!(budget.seconds > 0) || requested <= 0 || options.paths > 0) {
        sample_vpls(scene, camera, options, set);
        return requested;
    }
    const auto start = std::chrono::steady_clock::now();
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    // Step 1: probes of kVplFirstProbe, twice that, ..., each built (and timed with what the
    // caller builds over it), until one took kVplProbeShare of the budget, or its mean cost says
    // the whole count fits. The last is kept: where no more fit, it is the set.
    VplProbe smaller, larger;
    PointLightSet last;
    for (int n = kVplFirstProbe; 4 * int64_t(n) <= requested; n *= 2) {
        VplOptions probe = options;
        probe.count = n;
        last = PointLightSet();
        auto t0 = std::chrono::steady_clock::now();
        sample_vpls(scene, camera, probe, last);
        if (budget.also_timed) budget.also_timed(last);
        smaller = larger;
        larger = {n, since(t0)};
        double left = budget.seconds - since(start);
        if (larger.seconds * double(requested) / double(n) <= left) break;
        if (larger.seconds >= kVplProbeShare * budget.seconds) break;
    }
    // Step 2: the count that fits the time left (the last probe's, already built, where no
    // more fit), the least over the ranks (every rank must build the same set, and each timed
    // its own probes).
    int count = fit_vpl_count(requested, smaller, larger, budget.seconds - since(start));
    count = std::max(count, larger.count);
    if (budget.world && budget.world->size() > 1)
        count = int(budget.world->all_min(int64_t(count)));
    // Step 3: the set: the last probe's where it has that count (sample_vpls made it), else
    // built.
    if (count == larger.count) {
        append_set(std::move(last), set);
        return count;
    }
    VplOptions o = options;
    o.count = count;
    sample_vpls(scene, camera, o, set);
    return count;
}

std::string vpl_budget_warning(const PointLightSet& set, const char* setting) {
    if (set.vpl_count_used >= set.vpl_count_requested) return "";
    return fmt::format(
        "to build the VPLs within {:.0f}% of --time-limit, {} was reduced from {} to {} "
        "(the same estimate, with more noise): a longer time limit lifts it",
        100 * kVplBuildTimeShare, setting, set.vpl_count_requested, set.vpl_count_used);
}

nlohmann::json vpl_budget_json(const PointLightSet& set) {
    return {{"vpl_count_requested", set.vpl_count_requested},
            {"vpl_count_used", set.vpl_count_used}};
}

}  // namespace ml
