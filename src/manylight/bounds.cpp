#include "manylight/bounds.h"

#include <algorithm>

namespace ml {

namespace {

// Squared distance from x to the box, rounded down a little so that it never exceeds the squared
// distance to any point of the box as float arithmetic computes it.
float min_distance_squared(const Bounds3& b, const Vec3& x) {
    Vec3 d = vmax(vmax(b.lo - x, x - b.hi), Vec3(0, 0, 0));
    return length_squared(d) * (1 - 1e-6f);
}

// The smallest angle between the unit `axis` and p - x over the points p of the box, as its
// cosine and sine (Walter et al.'s bound: in a frame whose z is the axis, every point of the box
// has height z <= z_max and distance from the axis r >= r_min, so the angle is at least
// atan2(r_min, z_max)). Unlike a bounding cone it stays tight for flat boxes seen edge-on, such as
// the point lights of an area light seen from the ceiling around it. The ranges of the three
// frame coordinates over the box come from its extents, coordinate by coordinate (they are
// linear in p), with no corner loop and no trigonometry.
struct AngleCS {
    float cos, sin;
};
AngleCS min_angle_to_box(const Vec3& axis, const Bounds3& b, const Vec3& x) {
    Vec3 s, t;
    coordinate_system(axis, &s, &t);
    Vec3 lo = b.lo - x, hi = b.hi - x;
    auto range = [&](const Vec3& a, float* mn, float* mx) {
        *mn = *mx = 0;
        for (int i = 0; i < 3; ++i) {
            float u = a[i] * lo[i], v = a[i] * hi[i];
            *mn += std::min(u, v);
            *mx += std::max(u, v);
        }
    };
    float s_lo, s_hi, t_lo, t_hi, z_lo, z_hi;
    range(s, &s_lo, &s_hi);
    range(t, &t_lo, &t_hi);
    range(axis, &z_lo, &z_hi);
    // In front of the axis's plane (z_max > 0) the angle grows with r, so the nearest r bounds
    // it; behind it the angle shrinks as r grows, so the farthest r does.
    float rs, rt;
    if (z_hi > 0) {
        auto nearest = [](float l, float h) {
            return (l <= 0 && h >= 0) ? 0.f : std::min(std::abs(l), std::abs(h));
        };
        rs = nearest(s_lo, s_hi), rt = nearest(t_lo, t_hi);
    } else {
        rs = std::max(std::abs(s_lo), std::abs(s_hi)),
        rt = std::max(std::abs(t_lo), std::abs(t_hi));
    }
    float r = std::sqrt(rs * rs + rt * rt);
    float len = std::sqrt(r * r + z_hi * z_hi);
    if (!(len > 0)) return {1, 0};
    float c = z_hi / len, sn = r / len;
    // Less a small angle (2e-3 rad), so float rounding never makes the bound too small.
    constexpr float kCosEps = 0.999998f, kSinEps = 0.002f;
    if (sn <= kSinEps && c > 0) return {1, 0};
    return {c * kCosEps + sn * kSinEps, sn * kCosEps - c * kSinEps};
}

// cos(max(0, a - b)) for angles given by cosines and sines (a from the box, b a cone's half
// angle), or 0 when a - b reaches a right angle.
float cos_of_difference(AngleCS a, float cos_b) {
    if (a.cos >= cos_b) return 1;  // a <= b
    float sin_b = std::sqrt(std::max(0.f, 1 - cos_b * cos_b));
    return std::max(0.f, a.cos * cos_b + a.sin * sin_b);
}

}  // namespace

float emitter_cos_bound(LightNodeRef ref, const Vec3& x) {
    const LightTreeNode& node = ref.node;
    if (node.kind == PointLightKind::Omni || node.kind == PointLightKind::Directional) return 1;
    if (node.kind == PointLightKind::Glossy) {
        // The smallest angle between a lobe axis and a direction from the box to x picks the
        // falloff bin (cos_of_difference stops at a right angle: the bins end below it).
        float c = cos_of_difference(min_angle_to_box(-node.cone.axis, node.bounds, x),
                                    node.cone.cos_theta);
        return falloff_bound(ref.falloff, c);
    }
    // Oriented: the emitter's cosine between a normal of the cone and a direction from a point
    // of the box to x. Those directions lie in the reversed cone subtended by the box at x, so
    // the angle is at least angle(axis, x - c) - theta_normals - theta_box.
    if (node.cone.is_entire_sphere()) return 1;
    // The angle between the cone's axis and x - p, less the cone's half-angle.
    return cos_of_difference(min_angle_to_box(-node.cone.axis, node.bounds, x),
                             node.cone.cos_theta);
}

float geometric_bound(LightNodeRef ref, const Vec3& x) {
    const LightTreeNode& node = ref.node;
    if (node.kind == PointLightKind::Directional) return 1;
    float d2 = min_distance_squared(node.bounds, x);
    if (!(d2 > 0)) return kInfinity;
    float falloff = 1 / d2;
    if (node.kind == PointLightKind::Omni) return falloff;
    return emitter_cos_bound(ref, x) * falloff;
}

float receiver_cos_bound(const LightTreeNode& node, const Vec3& x, const Vec3& n, bool two_sided) {
    if (node.kind == PointLightKind::Directional) {
        // The directions towards the lights are the reversed cone of travel directions.
        auto side = [&](const Vec3& m) {
            float c = std::clamp(-dot(m, node.cone.axis), -1.f, 1.f);
            AngleCS a{c, std::sqrt(std::max(0.f, 1 - c * c))};
            // Widened by about 2e-3 rad against rounding, as min_angle_to_box is.
            return cos_of_difference(a, node.cone.cos_theta * 0.999998f - 0.002f);
        };
        return two_sided ? std::max(side(n), side(-n)) : side(n);
    }
    auto side = [&](const Vec3& m) {
        return std::max(0.f, min_angle_to_box(m, node.bounds, x).cos);
    };
    return two_sided ? std::max(side(n), side(-n)) : side(n);
}

RGB loose_node_bound(LightNodeRef ref, const Vec3& x, const RGB& material_all) {
    float gb = geometric_bound(ref, x);
    const RGB& intensity = ref.node.bound_intensity;
    RGB b;
    for (int c = 0; c < 3; ++c)
        b[c] = (gb == 0 || material_all[c] == 0 || intensity[c] == 0)
                   ? 0.f
                   : material_all[c] * gb * intensity[c];
    return b;
}

DirectionCone node_direction_cone(const LightTreeNode& node, const Vec3& x) {
    if (node.kind == PointLightKind::Directional) return reverse(node.cone);
    return bound_subtended_directions(node.bounds, x);
}

RGB material_bound(const LightTreeNode& node, const Vec3& x, const Bsdf& bsdf, const Vec3& wo) {
    // A Lambertian reflector: f is a constant on wo's side, so the bound is f times the largest
    // cosine towards the box, which the box itself bounds (more tightly than its cone does).
    if (node.kind != PointLightKind::Directional && bsdf.flags() == kBxdfDiffuseReflection) {
        Vec3 n = face_forward(bsdf.frame().n, wo);
        float cos_max = std::max(0.f, min_angle_to_box(n, node.bounds, x).cos);
        return cos_max > 0 ? bsdf.eval(wo, n) * cos_max : RGB();
    }
    return bsdf.max_value_bound(wo, node_direction_cone(node, x));
}

RGB node_error_bound(LightNodeRef ref, const Vec3& x, const Bsdf& bsdf, const Vec3& wo) {
    const RGB& intensity = ref.node.bound_intensity;
    if (intensity.is_black()) return RGB();
    float g = geometric_bound(ref, x);
    if (g == 0) return RGB();
    RGB m = material_bound(ref.node, x, bsdf, wo);
    RGB out;
    // 0 * infinity is 0 here: a channel the BSDF or the lights do not carry has no error.
    for (int c = 0; c < 3; ++c) {
        float mc = m[c], ic = intensity[c];
        out[c] = (mc == 0 || ic == 0) ? 0.f : mc * g * ic;
    }
    return out;
}

}  // namespace ml
