// Reconstruction cuts (Walter et al. 2005, Sec. 5; seed 004): `lightcuts.reconstruct` = B > 1
// computes full lightcuts only at a sparse grid of pixels (every B-th pixel in x and y, and the
// last row and column), and every other pixel sample shades its first gather point with a
// reconstruction cut built from the cuts of its block's four corners (the same sample index):
//
// 1. Image space: the corners must agree with the sample: each has a first gather point, with the
//    sample's material, a shading normal within kReconstructNormalCos of its own, and lying near
//    its tangent plane (no depth step). Else the sample computes its own full lightcut (the
//    block is refined down to that pixel).
// 2. Light tree, top down from each root: a node that some corner's cut refined (it lies above
//    that cut) is split. A node that every corner's cut holds, itself or through an ancestor, is
//    shaded by the sample's own representative, scaled to the cluster as lightcuts does, with the
//    visibility the corners agree on: all saw their representative of it: seen, with no shadow
//    ray; all found theirs blocked: nothing; they disagree (a shadow boundary), or none cast a
//    ray: the sample casts its own shadow ray, as lightcuts would.
//
// So the reconstruction cut is the union of the corners' cuts, fine wherever any of them needed
// it, with no error bounds to compute and shadow rays only across shadow boundaries. Visibility
// between the corners is interpolated: a shadow smaller than a block that touches no corner is
// missed, the price Walter et al. name. Later gather points of a path (behind mirrors and glass)
// always get full cuts.
#pragma once

#include <span>
#include <vector>

#include "manylight/gather.h"
#include "manylight/light_tree.h"
#include "manylight/many_lights.h"

namespace ml {

// Corners whose shading normals are further apart than this (cosine) refine the block.
constexpr float kReconstructNormalCos = 0.9f;
// A corner further off the sample's tangent plane than this times its distance refines it.
constexpr float kReconstructPlaneSlope = 0.1f;

// One node of a full lightcut and what its representative's shadow ray found.
struct CutNode {
    int32_t node;
    ShadowResult shadow;
    bool operator<(const CutNode& o) const { return node < o.node; }
};

// A sparse sample's full lightcut at its first gather point: what the reconstruction cuts of the
// samples around it read.
struct SparseCut {
    bool valid = false;  // the sample has a first gather point (else nothing below is set)
    const Material* material = nullptr;
    Vec3 p, n;                 // its position and shading normal
    std::vector<CutNode> cut;  // sorted by node
};

// Whether a sample whose first gather point is g may reconstruct from `corners` (step 1).
bool corners_agree(const GatherPoint& g, std::span<const SparseCut* const> corners);

// What the reconstruction cut gives at g (step 2), shading with representative k of each node;
// *nodes receives the cut's size.
RGB reconstruction_cut(const Scene& scene, const PointLightSet& set,
                       const ManyLightSettings& settings, const LightTree& tree,
                       const GatherPoint& g, int k, std::span<const SparseCut* const> corners,
                       int* nodes);

}  // namespace ml
