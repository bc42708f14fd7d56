#include "geometry/curves.h"

#include <algorithm>
#include <cmath>

namespace ml {

namespace {

Vec3 lerp3(float t, const Vec3& a, const Vec3& b) { return a * (1 - t) + b * t; }

// The cubic Bezier control points of a segment given in its own basis and degree (polar forms
// of the uniform B-spline and of the quadratic; a quadratic is raised to a cubic).
void to_cubic_bezier(const Vec3* cp, int degree, bool bspline, Vec3 out[4]) {
    if (degree == 2) {
        Vec3 q[3] = {cp[0], cp[1], cp[2]};
        if (bspline) {
            q[0] = lerp3(0.5f, cp[0], cp[1]);
            q[2] = lerp3(0.5f, cp[1], cp[2]);
        }
        out[0] = q[0];
        out[1] = q[0] + (q[1] - q[0]) * (2.f / 3.f);
        out[2] = q[2] + (q[1] - q[2]) * (2.f / 3.f);
        out[3] = q[2];
        return;
    }
    if (!bspline) {
        for (int i = 0; i < 4; ++i) out[i] = cp[i];
        return;
    }
    // Knots uniform: the Bezier points are the polar values f(222), f(223), f(233), f(333) of
    // the de Boor points f(012), f(123), f(234), f(345).
    Vec3 b122 = lerp3(2.f / 3.f, cp[0], cp[1]);
    Vec3 b223 = lerp3(1.f / 3.f, cp[1], cp[2]);
    Vec3 b233 = lerp3(2.f / 3.f, cp[1], cp[2]);
    Vec3 b334 = lerp3(1.f / 3.f, cp[2], cp[3]);
    out[0] = lerp3(0.5f, b122, b223);
    out[1] = b223;
    out[2] = b233;
    out[3] = lerp3(0.5f, b233, b334);
}

// pbrt-v4's ribbon normal along a segment: the spherical interpolation of its end normals.
Vec3 ribbon_normal(const Vec3& n0, const Vec3& n1, float u) {
    float angle = safe_acos(dot(n0, n1));
    if (angle < 1e-6f) return n0;
    float inv = 1 / std::sin(angle);
    return n0 * (std::sin((1 - u) * angle) * inv) + n1 * (std::sin(u * angle) * inv);
}

}  // namespace

std::unique_ptr<TriangleMesh> make_curves(const ParameterList& params, const FileLoc& loc) {
    auto at = [&](const char* name) {
        const Param* p = params.find(name);
        return p ? p->loc : loc;
    };
    const float width = params.get_float("width", 1.f);
    const float width0 = params.get_float("width0", width);
    const float width1 = params.get_float("width1", width);
    for (const char* name : {"width", "width0", "width1"})
        if (params.find(name) && !(params.get_float(name, 1.f) >= 0))
            throw_input_error(at(name), "curve: \"{}\" must not be negative", name);
    const int degree = params.get_int("degree", 3);
    if (degree != 2 && degree != 3)
        throw_input_error(at("degree"), "curve: \"degree\" {}: only 2 and 3 are supported", degree);
    const std::string basis = params.get_string("basis", "bezier");
    if (basis != "bezier" && basis != "bspline")
        throw_input_error(at("basis"),
                          "curve: unknown basis \"{}\" (\"bezier\" and \"bspline\" are supported)",
                          basis);
    const bool bspline = basis == "bspline";
    std::vector<Vec3> cp = params.get_point3s("P");
    if (cp.empty()) throw_input_error(at("P"), "curve: \"point3 P\" is required");
    size_t segments = 0;
    if (!bspline) {
        if (cp.size() < size_t(degree) + 1 || (cp.size() - 1) % size_t(degree) != 0)
            throw_input_error(at("P"),
                              "curve: {} control points: a degree {} Bezier curve needs {} + n * "
                              "{} (n >= 0)",
                              cp.size(), degree, degree + 1, degree);
        segments = (cp.size() - 1) / size_t(degree);
    } else {
        if (cp.size() < size_t(degree) + 1)
            throw_input_error(at("P"),
                              "curve: {} control points: a degree {} B-spline needs at least {}",
                              cp.size(), degree, degree + 1);
        segments = cp.size() - size_t(degree);
    }
    const std::string type_name = params.get_string("type", "flat");
    CurveSet set;
    if (type_name == "flat")
        set.type = CurveType::flat;
    else if (type_name == "cylinder")
        set.type = CurveType::cylinder;
    else if (type_name == "ribbon")
        set.type = CurveType::ribbon;
    else
        throw_input_error(at("type"),
                          "curve: unknown type \"{}\" (\"flat\", \"cylinder\" and \"ribbon\" are "
                          "supported)",
                          type_name);
    // As pbrt-v4, normals serve ribbons only (pbrt-v4 warns and ignores them on other types).
    std::vector<Vec3> n = params.get_normals("N");
    if (set.type == CurveType::ribbon) {
        if (n.empty())
            throw_input_error(at("N"),
                              "curve: a \"ribbon\" curve needs \"normal N\", one at each "
                              "segment end");
        if (n.size() != segments + 1)
            throw_input_error(at("N"), "curve: {} normals \"N\" for {} segments: {} are needed",
                              n.size(), segments, segments + 1);
        for (Vec3& v : n) {
            if (!(length_squared(v) > 0))
                throw_input_error(at("N"), "curve: a normal \"N\" is zero");
            v = normalize(v);
        }
    }
    // pbrt-v4 splits each segment 2^splitdepth times for its own intersector; Embree needs no
    // splitting, and the split pieces keep the segment's (u, v), so it changes nothing here.
    if (params.get_int("splitdepth", 3) < 0)
        throw_input_error(at("splitdepth"), "curve: \"splitdepth\" must not be negative");

    auto mesh = std::make_unique<TriangleMesh>();
    mesh->p.resize(4 * segments);
    set.width.resize(2 * segments);
    for (size_t s = 0; s < segments; ++s) {
        size_t first = bspline ? s : s * size_t(degree);
        to_cubic_bezier(&cp[first], degree, bspline, &mesh->p[4 * s]);
        // The width runs linearly from width0 to width1 over the segments, as in pbrt-v4.
        set.width[2 * s] = lerp(float(s) / float(segments), width0, width1);
        set.width[2 * s + 1] = lerp(float(s + 1) / float(segments), width0, width1);
        if (set.type == CurveType::ribbon) {
            set.n.push_back(n[s]);
            set.n.push_back(n[s + 1]);
        }
    }
    mesh->curves = std::move(set);
    return mesh;
}

void transform_curves(CurveSet& curves, const Transform& to_world) {
    Vec3 x = to_world.vector(Vec3(1, 0, 0)), y = to_world.vector(Vec3(0, 1, 0)),
         z = to_world.vector(Vec3(0, 0, 1));
    float det = dot(x, cross(y, z));
    float scale = std::cbrt(std::abs(det));
    for (float& w : curves.width) w *= scale;
    for (Vec3& n : curves.n) {
        Vec3 t = to_world.normal(n);
        n = length_squared(t) > 0 ? normalize(t) : n;
    }
    curves.swaps_handedness = det < 0;
}

Vec3 eval_cubic_bezier(const Vec3 p[4], float u, Vec3* deriv) {
    float s = 1 - u;
    Vec3 a = p[1] - p[0], b = p[2] - p[1], c = p[3] - p[2];
    Vec3 d = (a * (s * s) + b * (2 * s * u) + c * (u * u)) * 3.f;
    if (length_squared(d) == 0) d = p[3] - p[0];
    *deriv = d;
    return p[0] * (s * s * s) + p[1] * (3 * s * s * u) + p[2] * (3 * s * u * u) +
           p[3] * (u * u * u);
}

void curve_interaction(const TriangleMesh& m, uint32_t seg, float u, const Ray& ray, float t,
                       float motion_time, SurfaceInteraction* si) {
    const CurveSet& c = *m.curves;
    // The segment where it is at the ray's time: control points, end widths and end normals.
    Vec3 cp[4], n_end[2];
    float w_end[2];
    for (int k = 0; k < 4; ++k) cp[k] = m.p[4 * size_t(seg) + size_t(k)];
    for (int k = 0; k < 2; ++k) {
        w_end[k] = c.width[2 * seg + size_t(k)];
        if (!c.n.empty()) n_end[k] = c.n[2 * seg + size_t(k)];
    }
    if (m.moves()) {
        const float x = std::clamp(motion_time, 0.f, 1.f) * float(m.motion_steps - 1);
        const int s0 = std::min(int(x), m.motion_steps - 2);
        const float f = x - float(s0);
        const size_t np = m.p.size(), nw = c.width.size(), nn = c.n.size();
        auto mix = [f](const Vec3& a, const Vec3& b) { return a * (1 - f) + b * f; };
        for (int k = 0; k < 4; ++k) {
            const size_t i = 4 * size_t(seg) + size_t(k);
            cp[k] = mix(m.motion_p[size_t(s0) * np + i], m.motion_p[size_t(s0 + 1) * np + i]);
        }
        for (int k = 0; k < 2; ++k) {
            const size_t i = 2 * size_t(seg) + size_t(k);
            w_end[k] = lerp(f, c.motion_width[size_t(s0) * nw + i],
                            c.motion_width[size_t(s0 + 1) * nw + i]);
            if (nn == 0) continue;
            const Vec3 n =
                mix(c.motion_n[size_t(s0) * nn + i], c.motion_n[size_t(s0 + 1) * nn + i]);
            n_end[k] = length_squared(n) > 0 ? normalize(n) : n_end[k];
        }
    }
    u = std::clamp(u, 0.f, 1.f);
    Vec3 dpdu;
    const Vec3 pc = eval_cubic_bezier(cp, u, &dpdu);
    const float w = lerp(u, w_end[0], w_end[1]);
    const Vec3 d = normalize(ray.d);
    const Vec3 p = ray.at(t);
    // Cross products taken in world space are negated under a handedness-swapping transform,
    // so that every direction below is pbrt-v4's, which takes them in object space.
    const float sign = c.swaps_handedness ? -1.f : 1.f;
    // Across the curve as seen along the ray: pbrt-v4's v grows this way.
    Vec3 across = cross(d, dpdu);
    if (length_squared(across) > 0) {
        across = normalize(across) * sign;
    } else {
        Vec3 other;
        coordinate_system(d, &across, &other);
    }
    float hit_width = w;
    Vec3 dpdv;
    if (c.type == CurveType::ribbon) {
        // The ribbon's width as seen along the ray (pbrt-v4 scales by |n . d|).
        Vec3 nh = ribbon_normal(n_end[0], n_end[1], u);
        hit_width = w * std::abs(dot(nh, d));
        Vec3 side = cross(nh, dpdu);
        dpdv = (length_squared(side) > 0 ? normalize(side) * sign : across) * hit_width;
    } else {
        dpdv = across * w;
    }
    float v = hit_width > 0 ? 0.5f + dot(p - pc, across) / hit_width : 0.5f;
    v = std::clamp(v, 0.f, 1.f);
    if (c.type == CurveType::cylinder) {
        // pbrt-v4's tube: dp/dv turned about dp/du by -theta, theta from -90 to 90 degrees
        // across the width, so that the normal sweeps half a circle.
        float theta = lerp(v, -0.5f * kPi, 0.5f * kPi);
        Vec3 k = normalize(dpdu);
        dpdv = dpdv * std::cos(theta) - cross(k, dpdv) * std::sin(theta);
    }
    Vec3 n = cross(dpdu, dpdv);
    n = length_squared(n) > 0 ? normalize(n) : d;
    // pbrt-v4's flip: reverse orientation xor swapped handedness; the world-space cross product
    // already carries the handedness.
    if (m.flip_normals != c.swaps_handedness) n = -n;
    si->p = p;
    si->p_error = Vec3(hit_width, hit_width, hit_width);
    si->t = t;
    si->time = ray.time;
    si->wo = -ray.d;
    si->uv = Vec2(u, v);
    si->dpdu = dpdu;
    si->dpdv = dpdv;
    si->ng = si->ns = n;
    si->material = m.material;
    si->area_light = nullptr;
    si->mesh = &m;
    si->prim_id = seg;
}

}  // namespace ml
