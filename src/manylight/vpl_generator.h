// Instant radiosity: virtual point lights (VPLs) deposited along light paths.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/interaction.h"
#include "lights/light_sampler.h"
#include "lights/point_lights.h"
#include "sampling/distributions.h"
#include "sampling/sampler.h"

namespace ml {

class Scene;

// Which VPL sampler (manylight/vpl_sampler.h) makes the set, and its settings.
enum class VplSamplerKind : uint8_t { Standard, Power, Bidirectional, Metropolis };

struct VplSamplerOptions {
    VplSamplerKind kind = VplSamplerKind::Standard;
    int pilot = 256;               // power, bidirectional: camera points of the pilot pass
    int pilot_paths = 1024;        // power: light paths of the pilot pass
    int candidates = 4;            // bidirectional: candidates per VPL kept by resampling
    int tries = 1;                 // metropolis: proposals per step (1: plain Metropolis-Hastings)
    int mir_pilot = 4096;          // metropolis: camera points that measure each VPL's power
    int mir_chains = 16;           // metropolis: independent chains sharing the steps
    float mir_large_step = 0.25f;  // metropolis: probability of a large step
    float mir_cap = 1;  // metropolis: the target's bound on a VPL's light at x1, times P_c (0: f)
};

// A sphere outside which no VPL is deposited (radius 0: none; bdlightcuts.vpl_region).
struct VplRegion {
    Vec3 center;
    float radius = 0;
    bool excludes(const Vec3& p) const {
        return radius > 0 && distance_squared(p, center) > radius * radius;
    }
};

struct VplOptions {
    int count = 10000;  // target: paths are traced until at least this many VPLs exist
    int max_depth = 5;  // most VPLs along one light path
    GlossyVpls glossy = GlossyVpls::Bsdf;  // VPLs on glossy surfaces (point_light.h)
    uint64_t seed = 0;
    VplSamplerOptions sampler;
    // The samplers' variations of standard instant radiosity:
    // > 0: trace exactly this many paths (count is then ignored).
    size_t paths = 0;
    // Not empty: the probability of starting a path at each light (scene light order) instead
    // of the lights' power (power sampling); every light that emits must have a positive one.
    std::vector<float> light_pmf;
    // Deposit only where the path arrives from a specular bounce (bidirectional sampling makes
    // the other VPLs from the camera).
    bool after_specular_only = false;
    // Emission focus: a sphere around what the camera sees (focus_radius 0: none). The lights
    // whose paths start on a disk over the whole scene (distant and infinite lights,
    // Light::emission_sphere) start the share focus_share of them on the sphere's shadow on that
    // disk instead, and every such path is weighed by the mixture's density, so that the VPLs
    // stay unbiased. Where the camera sees a room in a large scene (a classroom on a ground
    // plane hundreds of metres across), most paths over the whole disk miss the room.
    Vec3 focus_center;
    float focus_radius = 0;
    float focus_share = 0;
    // VPLs are deposited only within it (the paths go on either way).
    VplRegion region;
};

// Appends VPLs to set.lights (their surfaces to set.surfaces, the surfaces' Bxdfs to set.arenas)
// and adds to set.vpls and set.light_paths. Each VPL's flux is the light path's throughput
// divided by the number of paths traced, so the VPLs' emission estimates the indirect light
// without bias. Deterministic for a seed: path k draws its numbers from pixel (k mod 2^20,
// k / 2^20) of an independent sampler, and paths are kept in order whatever the thread count.
// With `vpl_lights`, the index of the light each VPL's path started from (one per VPL added).
void generate_vpls(const Scene& scene, const VplOptions& options, PointLightSet& set,
                   std::vector<int>* vpl_lights = nullptr);

// The VPLs of some light paths (or other samples), fluxes not yet divided by the sample count.
struct VplChunk {
    std::vector<PointLight> lights;
    std::vector<VplSurface> surfaces;  // PointLight::surface indexes these (chunk-local)
    std::vector<uint32_t> path_end;    // lights.size() after each path
    std::vector<int> path_light;       // the light each path started from
    std::unique_ptr<ScratchBuffer> arena;
};

// Light paths of standard instant radiosity, one at a time.
class VplTracer {
public:
    VplTracer(const Scene& scene, const VplOptions& options);
    // Paths chunk_index * chunk_paths onwards, path k from pixel (k mod 2^20, k / 2^20) of an
    // independent sampler of options.seed.
    void trace_chunk(size_t chunk_index, size_t chunk_paths, VplChunk& chunk) const;
    // One path's VPLs into chunk, its numbers from `sampler`; returns the index of the light it
    // started from (-1: none). In a scene that moves, the path is traced at `time` when given
    // (a sampler that drew the time of the path's other part), else at a time it draws.
    int trace_path(Sampler& sampler, ScratchBuffer& scratch, VplChunk& chunk,
                   const float* time = nullptr) const;

private:
    // Emission focus (VplOptions::focus_*) for a light whose paths start on the disk of the
    // sphere (center, radius): on_focus, le's origin moves to the focus's shadow (u_pos placing
    // it there); either way pdf_pos becomes the mixture's density at the origin.
    void focus_emission(const Vec3& center, float radius, bool on_focus, const Vec2& u_pos,
                        LightLeSample* le) const;
    const Scene& m_scene;
    VplOptions m_options;
    LightSampler m_light_sampler;
    Distribution1D m_light_pmf;
};

// A VPL at si for flux `beta` arriving from si.wo on a surface with BSDF `bsdf` (made from si),
// appended to chunk (nothing for a surface whose VPL would give no light).
void deposit_vpl(const SurfaceInteraction& si, const Bsdf& bsdf, const RGB& beta, GlossyVpls glossy,
                 VplChunk& chunk);
// A VPL at a scattering inside a medium of phase asymmetry g, for flux `beta` arriving from wi
// (unit, pointing back where the light came from): it re-emits through the phase function
// (transport/phase_bxdf.h), as an omni light where it is isotropic, else a glossy one about the
// direction it favours. Appended to chunk.
void deposit_medium_vpl(const Vec3& p, const Vec3& wi, float g, const RGB& beta, VplChunk& chunk);
// Appends the first `count` VPLs of `chunks` (in order) to set, fluxes times `scale`.
void append_vpls(std::vector<VplChunk>& chunks, size_t count, float scale, PointLightSet& set);
// Appends `pl` scaled by `scale` to `lights`, with its surface (if it has one, an index into
// `surfaces`) copied into `out_surfaces` and scaled alike.
void append_scaled_vpl(const PointLight& pl, const std::vector<VplSurface>& surfaces, float scale,
                       std::vector<PointLight>& lights, std::vector<VplSurface>& out_surfaces);

// An estimate of the largest BSDF value max_w f(w, wi) (times |cos(w, n)| when `with_cos`) over
// every direction w, by evaluation at probe directions and a safety margin; used as the bound
// `intensity` of glossy VPLs until BSDFs bound themselves.
RGB estimate_max_bsdf_value(const Bsdf& bsdf, const Vec3& wi, bool with_cos,
                            bool diffuse_only = false);

}  // namespace ml
