#include "lights/light_bounds.h"

#include <algorithm>
#include <cmath>

namespace ml {
float LightBounds::importance(const Vec3& p, const Vec3& n) const {
    if (phi <= 0 || box.empty()) return 0;
    return ImportanceBounds(*this).importance(p, n);
}

LightBounds union_bounds(const LightBounds& a, const LightBounds& b) {
    if (a.phi <= 0) return b;
    if (b.phi <= 0) return a;
    DirectionCone cone =
        union_cones(DirectionCone(a.w, a.cos_theta_o), DirectionCone(b.w, b.cos_theta_o));
    LightBounds r;
    r.box = a.box;
    r.box.expand(b.box);
    r.w = cone.axis;
    r.phi = a.phi + b.phi;
    r.cos_theta_o = std::max(-1.f, cone.cos_theta);
    r.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    r.two_sided = a.two_sided || b.two_sided;
    return r;
}

}  // namespace ml
