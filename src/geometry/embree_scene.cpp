#include "geometry/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <mutex>
#include <source_location>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/rng.h"
#include "core/stats.h"
#include "geometry/alpha_test.h"
#include "geometry/curves.h"

namespace ml {

namespace {
// Hits at t = 0 do not count. Embree accepts t >= tnear; an origin exactly on a plane (a point
// whose error bound is zero, so offset_ray_origin leaves it there) computes t = 0 exactly for
// that plane, which pbrt-v4's intersector rejects (t must exceed its error bound) and so do we.
constexpr float kTNear = std::numeric_limits<float>::min();

const char* embree_error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_UNKNOWN:
            return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
    }
    return "error";
}

// pbrt-v4's stochastic alpha test, as an Embree filter: a candidate hit on a cut-out mesh is
// dropped where alpha is 0, and where alpha is fractional when a uniform number drawn by hashing
// the ray (origin and direction, as pbrt-v4's HashFloat(ray.o, ray.d)) and the primitive exceeds
// alpha. Hashing rather than sampling keeps the test the same for the same ray, and the primitive
// in the hash keeps layers of cut-outs along one ray independent (pbrt-v4 gets that by
// re-spawning the ray past each rejected hit). Camera, bounce and shadow rays share the filter.
// alpha_at(mesh, o, d, t, primitive, i): alpha at candidate hit i.
template <typename AlphaAt>
void filter_by_alpha(const RTCFilterFunctionNArguments* args, AlphaAt&& alpha_at) {
    const auto* mesh = static_cast<const TriangleMesh*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        RTCRayN* ray = args->ray;
        const unsigned N = args->N;
        Vec3 o(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
        Vec3 d(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
        const unsigned prim = RTCHitN_primID(args->hit, N, i);
        const float a = alpha_at(*mesh, o, d, RTCRayN_tfar(ray, N, i), prim, i);
        if (a >= 1) continue;
        if (!alpha_keeps(a, hash_ints(float_bits(o.x, o.y), float_bits(o.z, d.x),
                                      float_bits(d.y, d.z), prim)))
            args->valid[i] = 0;
    }
}

// On triangles: alpha at the hit point, its texture coordinates and geometric normal.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
    filter_by_alpha(args, [args](const TriangleMesh& mesh, const Vec3& o, const Vec3& d, float t,
                                 unsigned prim, unsigned i) {
        RTCHitN* hit = args->hit;
        const unsigned N = args->N;
        const float u = RTCHitN_u(hit, N, i), v = RTCHitN_v(hit, N, i), w = 1.f - u - v;
        Vec2 uv0(0, 0), uv1(1, 0), uv2(1, 1);
        if (!mesh.uv.empty()) {
            uv0 = mesh.uv[mesh.indices[3 * prim]];
            uv1 = mesh.uv[mesh.indices[3 * prim + 1]];
            uv2 = mesh.uv[mesh.indices[3 * prim + 2]];
        }
        const Vec3 ng(RTCHitN_Ng_x(hit, N, i), RTCHitN_Ng_y(hit, N, i), RTCHitN_Ng_z(hit, N, i));
        return mesh.alpha->eval(o + d * t, uv0 * w + uv1 * u + uv2 * v,
                                length_squared(ng) > 0 ? normalize(ng) : ng);
    });
}

// On curves: alpha at the hit point, (u, v) and normal as the hit's interaction has them (pbrt-v4
// evaluates a curve's alpha there too), the curve where the ray's time (Embree's 0 to 1) puts it.
void curve_alpha_filter(const RTCFilterFunctionNArguments* args) {
    filter_by_alpha(args, [args](const TriangleMesh& mesh, const Vec3& o, const Vec3& d, float t,
                                 unsigned prim, unsigned i) {
        SurfaceInteraction si;
        curve_interaction(mesh, prim, RTCHitN_u(args->hit, args->N, i), Ray{o, d}, t,
                          RTCRayN_time(args->ray, args->N, i), &si);
        return mesh.alpha->eval(si.p, si.uv, si.ng);
    });
}

}  // namespace

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    // The first error Embree reported through its callback, raised by check() as InternalError.
    // The callback only records it: it runs inside Embree's C API (and on its build threads),
    // which an exception must not cross.
    std::mutex mutex;
    std::string error;
    static void on_error(void* user, RTCError code, const char* message) {
        Impl& impl = *static_cast<Impl*>(user);
        std::lock_guard<std::mutex> lock(impl.mutex);
        if (impl.error.empty())
            impl.error = fmt::format("Embree: {}{}{}", embree_error_name(code), message ? ": " : "",
                                     message ? message : "");
    }
    // Raises the error Embree reported since the last check, if any.
    void check(std::source_location where = std::source_location::current()) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error.empty()) throw InternalError(std::exchange(error, std::string()), where);
    }
};

EmbreeScene::EmbreeScene(const std::vector<const TriangleMesh*>& meshes, float time_start,
                         float time_end)
    : m_impl(std::make_unique<Impl>()),
      m_meshes(meshes),
      m_time_start(time_start),
      m_time_end(time_end) {
    m_impl->device = rtcNewDevice("verbose=0");
    if (!m_impl->device)
        throw InternalError(std::string("Embree: cannot create a device: ") +
                            embree_error_name(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(m_impl->device, &Impl::on_error, m_impl.get());
    m_impl->scene = rtcNewScene(m_impl->device);
    rtcSetSceneBuildQuality(m_impl->scene, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(m_impl->scene, RTC_SCENE_FLAG_ROBUST);
    for (size_t i = 0; i < meshes.size(); ++i) {
        const TriangleMesh& m = *meshes[i];
        if (m.curves) {
            add_curves(m, unsigned(i));
            continue;
        }
        RTCGeometry g = rtcNewGeometry(m_impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Shared buffers: Embree reads our arrays in place (it needs 16 bytes of padding after
        // the last vertex, which std::vector's growth gives no promise of, so copy positions).
        // A moving mesh: one vertex buffer per time step, which Embree interpolates linearly.
        const size_t nv = m.p.size();
        const int steps = m.moves() ? m.motion_steps : 1;
        if (m.moves()) rtcSetGeometryTimeStepCount(g, unsigned(steps));
        for (int step = 0; step < steps; ++step) {
            float* vb = static_cast<float*>(
                rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, unsigned(step),
                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
            m_impl->check();  // vb is null when Embree could not allocate it
            const Vec3* src = m.moves() ? &m.motion_p[size_t(step) * nv] : m.p.data();
            for (size_t k = 0; k < nv; ++k) {
                vb[3 * k] = src[k].x;
                vb[3 * k + 1] = src[k].y;
                vb[3 * k + 2] = src[k].z;
                m_bounds.expand(src[k]);
            }
        }
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(),
                                   0, 3 * sizeof(uint32_t), m.triangle_count());
        if (m.alpha) {
            rtcSetGeometryUserData(g, const_cast<TriangleMesh*>(&m));
            rtcSetGeometryIntersectFilterFunction(g, &alpha_filter);
            rtcSetGeometryOccludedFilterFunction(g, &alpha_filter);
        }
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(m_impl->scene, g, unsigned(i));
        rtcReleaseGeometry(g);
        m_impl->check();
    }
    rtcCommitScene(m_impl->scene);
    m_impl->check();
}

void EmbreeScene::add_curves(const TriangleMesh& m, unsigned id) {
    // Each segment its own four control points (x, y, z, radius); the width runs linearly along
    // a segment, so its Bezier control values are equally spaced. pbrt-v4's "flat" and
    // "cylinder" are both ribbons facing the ray (the cylinder is round in its shading normal
    // only), which Embree's flat curves are; "ribbon" is Embree's normal-oriented curve.
    const CurveSet& c = *m.curves;
    const size_t ns = c.segment_count();
    const bool ribbon = c.type == CurveType::ribbon;
    RTCGeometry g =
        rtcNewGeometry(m_impl->device, ribbon ? RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE
                                              : RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE);
    auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(uint32_t), ns));
    m_impl->check();
    for (size_t s = 0; s < ns; ++s) ib[s] = uint32_t(4 * s);
    // Embree cuts flat curves into linear pieces, 4 per segment by default, which shows as kinks
    // on long hairs; 16 follows pbrt-v4's own refinement (which stops at width / 20) closely.
    rtcSetGeometryTessellationRate(g, 16.f);
    // A moving curve mesh: one vertex (and normal) buffer per time step, which Embree
    // interpolates linearly, as curve_interaction does.
    const int steps = m.moves() ? m.motion_steps : 1;
    if (m.moves()) rtcSetGeometryTimeStepCount(g, unsigned(steps));
    for (int step = 0; step < steps; ++step) {
        const Vec3* p = m.moves() ? &m.motion_p[size_t(step) * m.p.size()] : m.p.data();
        const float* width =
            m.moves() ? &c.motion_width[size_t(step) * c.width.size()] : c.width.data();
        const Vec3* normal = !ribbon     ? nullptr
                             : m.moves() ? &c.motion_n[size_t(step) * c.n.size()]
                                         : c.n.data();
        float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX,
                                                                unsigned(step), RTC_FORMAT_FLOAT4,
                                                                4 * sizeof(float), 4 * ns));
        m_impl->check();
        float* nb = nullptr;
        if (ribbon) {
            nb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL,
                                                             unsigned(step), RTC_FORMAT_FLOAT3,
                                                             3 * sizeof(float), 4 * ns));
            m_impl->check();
        }
        for (size_t s = 0; s < ns; ++s) {
            for (int k = 0; k < 4; ++k) {
                const Vec3& q = p[4 * s + k];
                const float r = 0.5f * lerp(float(k) / 3.f, width[2 * s], width[2 * s + 1]);
                float* out = &vb[4 * (4 * s + k)];
                out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = r;
                m_bounds.expand(q - Vec3(r, r, r));
                m_bounds.expand(q + Vec3(r, r, r));
                if (nb) {
                    Vec3 n =
                        normal[2 * s] * (1 - float(k) / 3.f) + normal[2 * s + 1] * (float(k) / 3.f);
                    nb[3 * (4 * s + k)] = n.x, nb[3 * (4 * s + k) + 1] = n.y;
                    nb[3 * (4 * s + k) + 2] = n.z;
                }
            }
        }
    }
    if (m.alpha) {
        rtcSetGeometryUserData(g, const_cast<TriangleMesh*>(&m));
        rtcSetGeometryIntersectFilterFunction(g, &curve_alpha_filter);
        rtcSetGeometryOccludedFilterFunction(g, &curve_alpha_filter);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(m_impl->scene, g, id);
    rtcReleaseGeometry(g);
    m_impl->check();
}

EmbreeScene::~EmbreeScene() {
    if (m_impl->scene) rtcReleaseScene(m_impl->scene);
    if (m_impl->device) rtcReleaseDevice(m_impl->device);
}

bool EmbreeScene::intersect(const Ray& ray, SurfaceInteraction* si) const {
    return intersect_as(ray, si, false);
}

bool EmbreeScene::intersect_emitter(const Ray& ray, SurfaceInteraction* si) const {
    return intersect_as(ray, si, true);
}

bool EmbreeScene::intersect_as(const Ray& ray, SurfaceInteraction* si, bool emitters_only) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = kTNear;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = motion_time(ray.time);
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->scene, &ctx, &rh);
    stats::count_ray();
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    if (emitters_only && !m_meshes[rh.hit.geomID]->area_light) {
        si->area_light = nullptr;
        return true;
    }
    fill_interaction(ray, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar,
                     Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), si);
    return true;
}

namespace {

// Lane i of an Embree ray packet (RTCRay4/8 or the ray of an RTCRayHit4/8) set from `r`.
template <typename RayN>
void set_lane(RayN& p, int i, const Ray& r, float motion_time) {
    p.org_x[i] = r.o.x;
    p.org_y[i] = r.o.y;
    p.org_z[i] = r.o.z;
    p.dir_x[i] = r.d.x;
    p.dir_y[i] = r.d.y;
    p.dir_z[i] = r.d.z;
    p.tnear[i] = kTNear;
    p.tfar[i] = r.tmax;
    p.time[i] = motion_time;
    p.mask[i] = 0xffffffffu;
    p.id[i] = unsigned(i);
    p.flags[i] = 0;
}

void trace(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit4* rh) {
    rtcIntersect4(valid, s, c, rh);
}
void trace(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit8* rh) {
    rtcIntersect8(valid, s, c, rh);
}
void trace(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRay4* r) {
    rtcOccluded4(valid, s, c, r);
}
void trace(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRay8* r) {
    rtcOccluded8(valid, s, c, r);
}

}  // namespace

template <int N, typename RayHitN>
void EmbreeScene::intersect_n(const Ray* rays, const bool* active, SurfaceInteraction* si,
                              bool* hit) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) int valid[N];
    alignas(32) RayHitN rh;
    for (int i = 0; i < N; ++i) {
        valid[i] = active[i] ? -1 : 0;
        // Inactive lanes still hold finite values: Embree reads every lane.
        set_lane(rh.ray, i, active[i] ? rays[i] : Ray{Vec3(), Vec3(0, 0, 1), 0.f},
                 active[i] ? motion_time(rays[i].time) : 0.f);
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    trace(valid, m_impl->scene, &ctx, &rh);
    for (int i = 0; i < N; ++i) {
        if (!active[i]) continue;
        stats::count_ray();
        hit[i] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        if (!hit[i]) continue;
        fill_interaction(rays[i], rh.hit.geomID[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i],
                         rh.ray.tfar[i], Vec3(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]),
                         &si[i]);
    }
}

template <int N, typename RayN>
void EmbreeScene::occluded_n(const Ray* rays, const bool* active, bool* occluded) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) int valid[N];
    alignas(32) RayN r;
    for (int i = 0; i < N; ++i) {
        valid[i] = active[i] ? -1 : 0;
        set_lane(r, i, active[i] ? rays[i] : Ray{Vec3(), Vec3(0, 0, 1), 0.f},
                 active[i] ? motion_time(rays[i].time) : 0.f);
    }
    trace(valid, m_impl->scene, &ctx, &r);
    for (int i = 0; i < N; ++i) {
        if (!active[i]) continue;
        stats::count_shadow_ray();
        occluded[i] = r.tfar[i] < 0.f;
    }
}

void EmbreeScene::intersect4(const Ray rays[4], const bool active[4], SurfaceInteraction si[4],
                             bool hit[4]) const {
    intersect_n<4, RTCRayHit4>(rays, active, si, hit);
}

void EmbreeScene::intersect8(const Ray rays[8], const bool active[8], SurfaceInteraction si[8],
                             bool hit[8]) const {
    intersect_n<8, RTCRayHit8>(rays, active, si, hit);
}

void EmbreeScene::occluded4(const Ray rays[4], const bool active[4], bool occluded[4]) const {
    occluded_n<4, RTCRay4>(rays, active, occluded);
}

void EmbreeScene::occluded8(const Ray rays[8], const bool active[8], bool occluded[8]) const {
    occluded_n<8, RTCRay8>(rays, active, occluded);
}

bool EmbreeScene::occluded(const Ray& ray) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = kTNear;
    r.tfar = ray.tmax;
    r.time = motion_time(ray.time);
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(m_impl->scene, &ctx, &r);
    stats::count_shadow_ray();
    return r.tfar < 0.f;
}

float EmbreeScene::motion_time(float time) const {
    if (!(m_time_end > m_time_start)) return 0.f;
    return std::clamp((time - m_time_start) / (m_time_end - m_time_start), 0.f, 1.f);
}

void EmbreeScene::fill_interaction(const Ray& ray, unsigned geom_id, unsigned prim_id, float u,
                                   float v, float t, const Vec3& ng_embree,
                                   SurfaceInteraction* si) const {
    const TriangleMesh& m = *m_meshes[geom_id];
    if (m.curves) {
        curve_interaction(m, prim_id, u, ray, t, motion_time(ray.time), si);
        si->mesh_id = geom_id;
        return;
    }
    uint32_t i0 = m.indices[3 * prim_id], i1 = m.indices[3 * prim_id + 1],
             i2 = m.indices[3 * prim_id + 2];
    float w = 1.f - u - v;
    // A moving mesh: the vertices (and normals) where Embree found them, interpolated linearly
    // between the two time steps around the ray's time as Embree does.
    Vec3 p0, p1, p2, n0, n1, n2;
    if (m.moves()) {
        const size_t nv = m.p.size();
        float s = motion_time(ray.time) * float(m.motion_steps - 1);
        int k = std::min(int(s), m.motion_steps - 2);
        float f = s - float(k);
        auto at = [&](const std::vector<Vec3>& x, uint32_t i) {
            size_t a = size_t(k) * nv + i;
            return x[a] * (1 - f) + x[a + nv] * f;
        };
        p0 = at(m.motion_p, i0), p1 = at(m.motion_p, i1), p2 = at(m.motion_p, i2);
        if (!m.n.empty()) n0 = at(m.motion_n, i0), n1 = at(m.motion_n, i1), n2 = at(m.motion_n, i2);
    } else {
        p0 = m.p[i0], p1 = m.p[i1], p2 = m.p[i2];
        if (!m.n.empty()) n0 = m.n[i0], n1 = m.n[i1], n2 = m.n[i2];
    }
    // Interpolate the position from the vertices rather than o + t d: more accurate.
    si->p = p0 * w + p1 * u + p2 * v;
    // Whatever the barycentrics' own errors (they move p within the plane), the interpolation
    // leaves p within this of the triangle's plane (pbrt-v4's bound for its triangles).
    // (A moving mesh's vertices carry the rounding of their interpolation as well.)
    si->p_error = (vabs(p0 * w) + vabs(p1 * u) + vabs(p2 * v)) * gamma_bound(m.moves() ? 10 : 7);
    si->t = t;
    si->time = ray.time;
    si->wo = -ray.d;
    // Our winding convention: ng = (p1 - p0) x (p2 - p0), flipped by flip_normals.
    Vec3 ng = cross(p1 - p0, p2 - p0);
    float l = length(ng);
    ng = l > 0 ? ng / l : normalize(ng_embree);
    if (m.flip_normals) ng = -ng;
    // Texture coordinates default to pbrt's (0,0), (1,0), (1,1) per triangle.
    Vec2 uv0(0, 0), uv1(1, 0), uv2(1, 1);
    if (!m.uv.empty()) uv0 = m.uv[i0], uv1 = m.uv[i1], uv2 = m.uv[i2];
    si->uv = uv0 * w + uv1 * u + uv2 * v;
    // dp/du and dp/dv from the uv parameterisation (pbrt's Triangle::InteractionFromIntersection).
    Vec2 duv02 = uv0 - uv2, duv12 = uv1 - uv2;
    Vec3 dp02 = p0 - p2, dp12 = p1 - p2;
    float det = duv02.x * duv12.y - duv02.y * duv12.x;
    bool degenerate = std::abs(det) < 1e-9f;
    if (!degenerate) {
        float inv = 1.f / det;
        si->dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inv;
        si->dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inv;
        degenerate = length_squared(cross(si->dpdu, si->dpdv)) == 0.f;
    }
    if (degenerate) coordinate_system(ng, &si->dpdu, &si->dpdv);
    if (!m.n.empty()) {
        Vec3 ns = n0 * w + n1 * u + n2 * v;
        float ls = length_squared(ns);
        ns = ls > 0 ? ns / std::sqrt(ls) : ng;
        // As in pbrt-v4, the shading normals are authoritative for orientation.
        si->ns = ns;
        si->ng = face_forward(ng, ns);
    } else {
        si->ns = si->ng = ng;
    }
    si->material = m.material;
    si->area_light = m.area_light;
    si->mesh = &m;
    si->mesh_id = geom_id;
    si->prim_id = prim_id;
}

}  // namespace ml
