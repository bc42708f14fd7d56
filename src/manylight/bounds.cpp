#include "manylight/bounds.h"

namespace ml {

namespace {

// Squared distance from x to the box, rounded down a little so that it never exceeds the squared
// distance to any point of the box as float arithmetic computes it.
float min_distance_squared(const Bounds3& b, const Vec3& x) {
    Vec3 d = vmax(vmax(b.lo - x, x - b.hi), Vec3(0, 0, 0));
    return length_squared(d) * (1 - 1e-6f);
}

// The smallest angle between the unit `axis` and p - x over the points p of the box (Walter et
// al.'s bound: the box's corners relative to x, in a frame whose z is the axis, bound every
// point's height z <= z_max and distance from the axis r >= r_min, so the angle is at least
// atan2(r_min, z_max)). Unlike a bounding cone it stays tight for flat boxes seen edge-on, such as
// the point lights of an area light seen from the ceiling around it.
float min_angle_to_box(const Vec3& axis, const Bounds3& b, const Vec3& x) {
    Frame f = Frame::from_z(axis);
    Bounds3 local;
    for (int i = 0; i < 8; ++i) {
        Vec3 c((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
        local.expand(f.to_local(c - x));
    }
    // In front of the axis's plane (z_max > 0) the angle grows with r, so the nearest r bounds
    // it; behind it the angle shrinks as r grows, so the farthest r does.
    float r;
    if (local.hi.z > 0) {
        auto nearest = [](float lo, float hi) {
            return (lo <= 0 && hi >= 0) ? 0.f : std::min(std::abs(lo), std::abs(hi));
        };
        float rx = nearest(local.lo.x, local.hi.x), ry = nearest(local.lo.y, local.hi.y);
        r = std::sqrt(rx * rx + ry * ry);
    } else {
        float rx = std::max(std::abs(local.lo.x), std::abs(local.hi.x));
        float ry = std::max(std::abs(local.lo.y), std::abs(local.hi.y));
        r = std::sqrt(rx * rx + ry * ry);
    }
    // Less a small angle, so float rounding in the frame never makes the bound too small.
    return std::max(0.f, std::atan2(r, local.hi.z) - 2e-3f);
}

}  // namespace

float geometric_bound(const LightTreeNode& node, const Vec3& x) {
    if (node.kind == PointLightKind::Directional) return 1;
    float d2 = min_distance_squared(node.bounds, x);
    if (!(d2 > 0)) return kInfinity;
    float falloff = 1 / d2;
    if (node.kind == PointLightKind::Omni) return falloff;
    // Oriented: the emitter's cosine between a normal of the cone and a direction from a point
    // of the box to x. Those directions lie in the reversed cone subtended by the box at x, so
    // the angle is at least angle(axis, x - c) - theta_normals - theta_box.
    if (node.cone.is_entire_sphere()) return falloff;
    // Two lower bounds of the angle between the cone's axis and x - p: through the cone the box
    // subtends, and through the box itself; the larger holds.
    float theta = min_angle_to_box(-node.cone.axis, node.bounds, x);
    DirectionCone to_box = bound_subtended_directions(node.bounds, x);
    if (!to_box.is_entire_sphere())
        theta = std::max(theta, angle_between(node.cone.axis, -to_box.axis) - cone_angle(to_box));
    theta -= cone_angle(node.cone);
    if (theta >= kPi / 2) return 0;
    return std::cos(std::max(0.f, theta)) * falloff;
}

DirectionCone node_direction_cone(const LightTreeNode& node, const Vec3& x) {
    if (node.kind == PointLightKind::Directional) return reverse(node.cone);
    return bound_subtended_directions(node.bounds, x);
}

RGB material_bound(const LightTreeNode& node, const Vec3& x, const Bsdf& bsdf, const Vec3& wo) {
    RGB m = bsdf.max_value_bound(wo, node_direction_cone(node, x));
    // A Lambertian reflector: f is a constant on wo's side, so the bound is f times the largest
    // cosine towards the box, which the box itself bounds more tightly than its cone.
    if (node.kind != PointLightKind::Directional && bsdf.flags() == kBxdfDiffuseReflection) {
        Vec3 n = face_forward(bsdf.frame().n, wo);
        float theta = min_angle_to_box(n, node.bounds, x);
        float cos_max = theta >= kPi / 2 ? 0.f : std::cos(theta);
        RGB f = bsdf.eval(wo, n);
        for (int c = 0; c < 3; ++c) m[c] = std::min(m[c], f[c] * cos_max);
    }
    return m;
}

RGB node_error_bound(const LightTreeNode& node, const Vec3& x, const Bsdf& bsdf, const Vec3& wo) {
    if (node.intensity.is_black()) return RGB();
    float g = geometric_bound(node, x);
    if (g == 0) return RGB();
    RGB m = material_bound(node, x, bsdf, wo);
    RGB out;
    // 0 * infinity is 0 here: a channel the BSDF or the lights do not carry has no error.
    for (int c = 0; c < 3; ++c) {
        float mc = m[c], ic = node.intensity[c];
        out[c] = (mc == 0 || ic == 0) ? 0.f : mc * g * ic;
    }
    return out;
}

}  // namespace ml
