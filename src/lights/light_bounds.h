// What a light-tree node knows of the lights below it (Conty Estevez & Kulla 2018; pbrt-v4's
// LightBounds): where they are (a box), which way they emit (a cone of normals of half-angle
// theta_o, each normal emitting up to theta_e away from it), and how strongly (phi). importance()
// turns that into an estimate of the irradiance the lights could deliver to a shading point, which
// the tree light sampler (light_sampler.h) chooses children by.
//
// phi is in units that make importance() an irradiance: a point or spot light's luminous
// intensity I (irradiance I cos / d^2), an area light's radiance times its area, L A (irradiance
// about L A cos cos / d^2). pbrt-v4 uses 4 pi I for points and L A for areas, which favours point
// lights 4 pi times over area lights of equal effect; and it cannot compare the tree with
// infinite lights, which it samples with a fixed probability. Ours can (light_sampler.cpp).
#pragma once

#include "core/cone.h"
#include "core/math.h"

namespace ml {

struct LightBounds {
    Bounds3 box;
    Vec3 w{0, 0, 1};         // axis of the cone of emitter normals
    float phi = 0;           // see above; 0: emits nothing
    float cos_theta_o = 1;   // half-angle of the cone of normals
    float cos_theta_e = 0;   // how far from its normal a point emits (pi / 2: a diffuse face)
    bool two_sided = false;  // emits on both sides of each normal

    // Estimated irradiance at p (surface normal n; zero: none, as in a medium). Zero only where
    // no light of the bounds can reach p: every cone test is conservative.
    float importance(const Vec3& p, const Vec3& n) const;
};

// The bounds of both (phi adds up); an operand with phi = 0 leaves the other unchanged.
LightBounds union_bounds(const LightBounds& a, const LightBounds& b);

}  // namespace ml
