#include "manylight/bounds.h"

namespace ml {

namespace {

// Squared distance from x to the box, rounded down a little so that it never exceeds the squared
// distance to any point of the box as float arithmetic computes it.
float min_distance_squared(const Bounds3& b, const Vec3& x) {
    Vec3 d = vmax(vmax(b.lo - x, x - b.hi), Vec3(0, 0, 0));
    return length_squared(d) * (1 - 1e-6f);
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
    DirectionCone to_box = bound_subtended_directions(node.bounds, x);
    if (to_box.is_entire_sphere() || node.cone.is_entire_sphere()) return falloff;
    float theta =
        angle_between(node.cone.axis, -to_box.axis) - cone_angle(node.cone) - cone_angle(to_box);
    if (theta >= kPi / 2) return 0;
    return std::cos(std::max(0.f, theta)) * falloff;
}

DirectionCone node_direction_cone(const LightTreeNode& node, const Vec3& x) {
    if (node.kind == PointLightKind::Directional) return reverse(node.cone);
    return bound_subtended_directions(node.bounds, x);
}

RGB material_bound(const LightTreeNode& node, const Vec3& x, const Bsdf& bsdf, const Vec3& wo) {
    return bsdf.max_value_bound(wo, node_direction_cone(node, x));
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
