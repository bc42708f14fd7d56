// Lightcuts' error bounds (Walter et al. 2005, section 4.1): for a shading point x, upper bounds
// of the geometric term G and of the material term M over every light of a light-tree node, so
// that the node's error is at most M_ub * G_ub * V_ub * I_node with V_ub = 1 (I_node: the node's
// bound_intensity, which also covers its representatives' estimates).
//
// Each bound holds for every light of the node, whatever its position in the node's box and
// its direction in the node's cone: the exact contribution
//   sum_i f(wo, wi) |cos(n, wi)| I_i(-wi) / d_i^2     (directional lights: without the 1/d^2)
// never exceeds node_error_bound(). Oriented VPLs on surfaces kept with their BSDF (a coated
// base alone) are covered through the promise of point_light.h that their intensity bounds f,
// glossy VPLs through their falloff (intensity times it bounds f |cos| away from the lobe).
#pragma once

#include "core/color.h"
#include "core/cone.h"
#include "core/math.h"
#include "manylight/light_tree.h"
#include "materials/bsdf.h"

namespace ml {

// Upper bound of G over the node's lights at x (the 1/d^2 falloff, times the emitter's cosine
// for oriented lights and the falloff for glossy ones; 1 for directional lights). +infinity when
// x is inside the node's box.
float geometric_bound(LightNodeRef ref, const Vec3& x);

// The emitters' part of geometric_bound: an upper bound over the node's lights of the
// emitter's cosine (oriented) or falloff (glossy) towards x; 1 for omni and directional lights.
// x inside the node's box is fine (the bound is then usually 1).
float emitter_cos_bound(LightNodeRef ref, const Vec3& x);

// An upper bound of |cos(n, wi)| over the directions wi from x towards the node's lights, on n's
// side only (two_sided false: a surface that only reflects, n facing the viewer) or on both.
// Zero only when no light of the node is on a side that counts.
float receiver_cos_bound(const LightTreeNode& node, const Vec3& x, const Vec3& n, bool two_sided);

// The cheap bound a cut starts a node with: material_all (the BSDF's bound over every direction
// at x) times geometric_bound times the node's bound_intensity, channel by channel, with
// 0 * infinity taken as 0. Zero only when none of the node's lights can give x light.
RGB loose_node_bound(LightNodeRef ref, const Vec3& x, const RGB& material_all);

// The cone of directions from x towards the node's lights (the incident directions wi the
// material bound ranges over): towards the box for omni and oriented lights, the reverse of the
// travel directions for directional lights.
DirectionCone node_direction_cone(const LightTreeNode& node, const Vec3& x);

// Upper bound of f(wo, wi) |cos wi| over wi towards the node's lights (world-space wo, unit,
// pointing away from x).
RGB material_bound(const LightTreeNode& node, const Vec3& x, const Bsdf& bsdf, const Vec3& wo);

// M_ub * G_ub * bound_intensity: the node's error bound at x, what the cut loop compares with
// the current estimate. It bounds the exact sum over the node's lights and the node's estimate
// by any of its representatives (light_tree.h) alike. Zero when the node is dark or the BSDF cannot
// see it; may be +infinity (x inside the box, or a rough dielectric's transmission, see
// bxdf_bounds.cpp).
RGB node_error_bound(LightNodeRef ref, const Vec3& x, const Bsdf& bsdf, const Vec3& wo);

}  // namespace ml
