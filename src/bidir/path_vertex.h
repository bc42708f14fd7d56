// Vertices of bidirectional subpaths and the densities BDPT's MIS weights are made of (Veach's
// thesis, chapter 10; pbrt-v4's Vertex). Every density stored on a vertex is per unit area at
// that vertex, except where the vertex stands for an infinite light: there it is per solid angle.
#pragma once

#include "camera/camera.h"
#include "geometry/interaction.h"
#include "lights/light.h"
#include "lights/light_sampler.h"
#include "materials/bsdf.h"
#include "media/medium.h"
#include "scene/scene.h"

namespace ml {

// What the subpath machinery needs of the scene.
struct BdptScene {
    const Scene& scene;
    const PerspectiveCamera& camera;
    const LightSampler& light_sampler;  // chooses the light of light subpaths and of s = 1
    Vec3 scene_center;                  // bounding sphere: infinite lights' ray origins
    float scene_radius = 0;

    BdptScene(const Scene& s, const PerspectiveCamera& c, const LightSampler& ls)
        : scene(s), camera(c), light_sampler(ls) {
        s.bounds().bounding_sphere(&scene_center, &scene_radius);
    }
    // Per-solid-angle density, summed over the infinite lights, of a light subpath starting
    // with direction w (travelling away from the light).
    float infinite_light_density(const Vec3& w) const;
};

// Medium: a scattering event inside a participating medium (its phase function scatters).
enum class VertexKind : uint8_t { Camera, Light, Surface, Medium };

struct PathVertex {
    VertexKind kind = VertexKind::Surface;
    // Sampled by a delta lobe here: no strategy can connect at this vertex.
    bool delta = false;
    RGB beta;  // the subpath's throughput up to and including this vertex (pbrt's beta)
    // Density of this vertex when sampled from its predecessor on its own subpath (pdf_fwd),
    // and from its successor, as the other subpath would have sampled it (pdf_rev).
    float pdf_fwd = 0, pdf_rev = 0;
    // Surfaces: the hit. Endpoints: p, and ng = ns (zero for points, directions and pinholes).
    SurfaceInteraction si;
    Bsdf bsdf;  // surfaces (empty on surfaces without a material: not connectible)
    // Surfaces: the shading normal of the hit before the material tilted it (bump mapping), so
    // that the BSDF can be made again elsewhere.
    Vec3 ns_hit;
    // Light endpoints: the light; null for the vertex of an escaped camera ray, which stands
    // for every infinite light at once.
    const Light* light = nullptr;
    // Surfaces: the participating medium the subpath arrived in; medium vertices: theirs.
    const Medium* medium = nullptr;

    // A scattering event at p in `m`, arrived at travelling along -wo.
    static PathVertex in_medium(const Vec3& p, const Vec3& wo, const Medium* m, float time,
                                const RGB& beta) {
        PathVertex v;
        v.kind = VertexKind::Medium;
        v.si.p = p;
        v.si.wo = wo;
        v.si.time = time;
        v.medium = m;
        v.beta = beta;
        return v;
    }

    static PathVertex camera(const Vec3& p, const Vec3& n, const RGB& beta) {
        PathVertex v;
        v.kind = VertexKind::Camera;
        v.si.p = p;
        v.si.ng = v.si.ns = n;
        v.beta = beta;
        return v;
    }
    // p_error: the error bound of a point on a surface (as SurfaceInteraction's).
    static PathVertex light_endpoint(const Light* light, const Vec3& p, const Vec3& n,
                                     const RGB& beta, float pdf_fwd, const Vec3& p_error = Vec3(),
                                     uint32_t prim = 0) {
        PathVertex v;
        v.kind = VertexKind::Light;
        v.light = light;
        v.si.p = p;
        v.si.p_error = p_error;
        v.si.prim_id = prim;
        v.si.ng = v.si.ns = n;
        v.beta = beta;
        v.pdf_fwd = pdf_fwd;
        return v;
    }

    const Vec3& p() const { return si.p; }
    const Vec3& ng() const { return si.ng; }
    const Vec3& ns() const { return si.ns; }
    bool on_surface() const { return !(si.ng == Vec3()); }
    // What a ray to or from this vertex moves it by (segment_ray): the lens, like points on no
    // surface, stays put.
    Vec3 offset() const { return kind == VertexKind::Camera ? Vec3() : si.offset(); }

    bool is_connectible() const {
        switch (kind) {
            case VertexKind::Camera:
                return true;
            case VertexKind::Light:
                return light && light->type() != LightType::DeltaDirection;
            case VertexKind::Surface:
                return bsdf && bsdf.has_nonspecular();
            case VertexKind::Medium:
                return true;
        }
        return false;
    }
    bool is_light() const {
        return kind == VertexKind::Light || (kind == VertexKind::Surface && si.area_light);
    }
    // A light no camera subpath can meet: a delta light, or an invisible area light (MIS
    // leaves out the strategies that would).
    bool is_delta_light() const {
        return kind == VertexKind::Light && light && !light->met_by_rays();
    }
    bool is_infinite_light() const {
        return kind == VertexKind::Light && (!light || light->type() == LightType::Infinite ||
                                             light->type() == LightType::DeltaDirection);
    }
    // The emitter this vertex lies on (area lights hit by camera subpaths, light endpoints).
    const Light* emitter() const { return kind == VertexKind::Light ? light : si.area_light; }

    // BSDF value towards `next` (surfaces), or the phase function's (medium vertices).
    RGB f(const PathVertex& next, TransportMode mode) const {
        Vec3 wi = next.p() - p();
        if (length_squared(wi) == 0) return RGB();
        if (kind == VertexKind::Medium) return RGB(hg_phase(si.wo, normalize(wi), medium->g()));
        if (kind != VertexKind::Surface || !bsdf) return RGB();
        return bsdf.eval(si.wo, normalize(wi), mode);
    }
    // The cosine a connection along unit direction w meets here: at surfaces the shading
    // normal's, elsewhere 1.
    float cos_towards(const Vec3& w) const {
        return kind == VertexKind::Surface ? abs_dot(ns(), w) : 1.f;
    }
    // The participating medium a ray leaving this vertex along w starts in (null: none).
    const Medium* medium_towards(const BdptScene& ctx, const Vec3& w) const;

    // Radiance this light vertex emits towards `v`.
    RGB Le(const BdptScene& ctx, const PathVertex& v) const;

    // A solid-angle density at this vertex turned into the area density at `next`.
    float convert_density(float pdf_solid_angle, const PathVertex& next) const {
        if (next.is_infinite_light()) return pdf_solid_angle;
        Vec3 w = next.p() - p();
        float d2 = length_squared(w);
        if (d2 == 0) return 0;
        if (next.on_surface()) pdf_solid_angle *= abs_dot(next.ng(), w / std::sqrt(d2));
        return pdf_solid_angle / d2;
    }

    // Area density at `next` of sampling it from this vertex, arrived at from `prev` (null for
    // camera and light endpoints).
    float pdf_area(const BdptScene& ctx, const PathVertex* prev, const PathVertex& next) const;
    // Area density at `v` of a light subpath leaving this light vertex towards it.
    float pdf_light(const BdptScene& ctx, const PathVertex& v) const;
    // Area density (solid angle for infinite lights) of a light subpath starting at this
    // light vertex and heading for `v`, light choice included.
    float pdf_light_origin(const BdptScene& ctx, const PathVertex& v) const;
};

// True if nothing blocks the segment between two vertices (offset off both surfaces).
bool mutually_visible(const Scene& scene, const PathVertex& a, const PathVertex& b);
// What passes between two vertices: 1 or 0 by mutually_visible in a scene without media, else
// the media's transmittance from a to b through interface surfaces (0 at any other).
RGB transmittance_between(const BdptScene& ctx, const PathVertex& a, const PathVertex& b,
                          Sampler& sampler);

}  // namespace ml
