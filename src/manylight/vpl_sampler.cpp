#include "manylight/vpl_sampler.h"

#include <algorithm>

#include "camera/camera.h"
#include "core/error.h"
#include "core/rng.h"
#include "sampling/warps.h"
#include "scene/scene.h"

namespace ml {

VplSamplerKind parse_vpl_sampler(const std::string& name) {
    if (name == "standard") return VplSamplerKind::Standard;
    if (name == "power") return VplSamplerKind::Power;
    if (name == "bidirectional") return VplSamplerKind::Bidirectional;
    if (name == "metropolis") return VplSamplerKind::Metropolis;
    throw UsageError("vpl.sampler must be standard, power, bidirectional or metropolis, not " +
                     name);
}

const char* vpl_sampler_name(VplSamplerKind kind) {
    switch (kind) {
        case VplSamplerKind::Standard:
            return "standard";
        case VplSamplerKind::Power:
            return "power";
        case VplSamplerKind::Bidirectional:
            return "bidirectional";
        case VplSamplerKind::Metropolis:
            return "metropolis";
    }
    return "?";
}

void sample_vpls(const Scene& scene, const PerspectiveCamera* camera, const VplOptions& options,
                 PointLightSet& set) {
    VplSamplerKind kind = options.sampler.kind;
    if (kind == VplSamplerKind::Standard) return generate_vpls(scene, options, set);
    if (!camera)
        throw UsageError(std::string("vpl.sampler=") + vpl_sampler_name(kind) +
                         " needs the camera; this caller has none");
    switch (kind) {
        case VplSamplerKind::Power:
            return sample_power_vpls(scene, *camera, options, set);
        case VplSamplerKind::Bidirectional:
            return sample_bidirectional_vpls(scene, *camera, options, set);
        default:
            return sample_metropolis_vpls(scene, *camera, options, set);
    }
}

PilotPoints camera_pilot_points(const Scene& scene, const PerspectiveCamera& camera, int count,
                                int max_depth, uint64_t seed) {
    PilotPoints pilot;
    pilot.arena = std::make_unique<ScratchBuffer>(size_t(std::max(count, 1)) * 1024 + 65536);
    auto sampler = create_sampler("independent", 1, hash_ints(seed, 0x70696c6f74ULL));
    // Film positions stratified (a Hammersley set under a random shift): the points spread over
    // the image as a render's pixels do.
    sampler->start_pixel_sample({0, 1}, 0);
    Vec2 shift = sampler->get_2d();
    for (int i = 0; i < count; ++i) {
        sampler->start_pixel_sample({i, 0}, 0);
        CameraSample cs;
        Vec2 u = shifted_hammersley(uint32_t(i), uint32_t(count), shift);
        cs.p_film = Vec2(u.x * float(camera.width()), u.y * float(camera.height()));
        cs.p_lens = sampler->get_2d();
        cs.time = sampler->get_1d();
        float camera_weight;
        Ray ray = camera.generate_ray(cs, &camera_weight);
        if (camera_weight == 0) continue;  // stopped by the realistic camera's lens
        RGB L, beta(camera_weight);
        GatherPoint g;
        for (int depth = 0;; ++depth) {
            if (!detail::next_gather_hit(scene, ray, *pilot.arena, beta, &L, &g)) break;
            g.beta = beta;
            if (g.bsdf.has_nonspecular()) {
                pilot.points.push_back(g);
                break;
            }
            if (depth == max_depth || !detail::continue_through_delta(g, *sampler, &beta, &ray))
                break;
        }
    }
    return pilot;
}

bool camera_focus_sphere(const Scene& scene, const PerspectiveCamera& camera, int count,
                         uint64_t seed, Vec3* center, float* radius) {
    PilotPoints pilot = camera_pilot_points(scene, camera, count, 8, seed);
    const size_t n = pilot.points.size();
    if (n < 16) return false;
    Bounds3 box;
    std::vector<float> c(n);
    for (int axis = 0; axis < 3; ++axis) {
        for (size_t i = 0; i < n; ++i) c[i] = pilot.points[i].si.p[axis];
        std::sort(c.begin(), c.end());
        const float lo = c[n / 20], hi = c[n - 1 - n / 20], grow = (hi - lo) / 10;
        box.lo[axis] = lo - grow;
        box.hi[axis] = hi + grow;
    }
    box.bounding_sphere(center, radius);
    return *radius > 0;
}

}  // namespace ml
