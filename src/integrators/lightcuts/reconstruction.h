// Reconstruction cuts (Walter et al. 2005, Sec. 5; seed 004): `lightcuts.reconstruct` = B > 1
// computes full lightcuts only at a sparse grid of pixels (every B-th pixel in x and y, and the
// last row and column), and every other pixel sample shades its first gather point with a
// reconstruction cut built from the cuts of its block's four corners (the same sample index):
//
// 1. Image space: the corners that agree with the sample: those with a first gather point of the
//    sample's material, a shading normal within kReconstructNormalCos of its own, lying near its
//    tangent plane (no depth step). With fewer than kReconstructMinCorners of them the sample
//    computes its own full lightcut (the block is refined down to that pixel); a sample beside a
//    material edge reconstructs from the corners on its side of it.
// 2. Light tree, top down from each root: a node that some agreeing corner's cut refined (it
//    lies above that cut) is split. A node that every one of their cuts holds, itself or through
//    an ancestor, is shaded by the sample's own representative, scaled to the cluster as
//    lightcuts does, with the visibility the corners agree on: all saw their representative of
//    it: seen, with no shadow ray; all found theirs blocked: nothing; they disagree (a shadow
//    boundary), or none cast a ray: the sample casts its own shadow ray, as lightcuts would.
//
// So the reconstruction cut is the union of the corners' cuts, fine wherever any of them needed
// it, with no error bounds to compute and shadow rays only across shadow boundaries. Visibility
// between the corners is interpolated: a shadow smaller than a block that touches no corner is
// missed, the price Walter et al. name. Later gather points of a path (behind mirrors and glass)
// always get full cuts. (Walter et al. refine a disagreeing block by computing full cuts at more
// sparse samples within it, level by level; here the samples of such a block compute their own.)
#pragma once

#include <array>
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
// A sample reconstructs from the corners that agree with it when there are at least this many.
constexpr int kReconstructMinCorners = 2;

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

// The corners a sample whose first gather point is g reconstructs from (step 1), into
// *agreeing; returns how many. It reconstructs from at least kReconstructMinCorners.
int agreeing_corners(const GatherPoint& g, std::span<const SparseCut* const> corners,
                     std::array<const SparseCut*, 4>* agreeing);

// What the reconstruction cut gives at g (step 2), shading with representative k of each node;
// *nodes receives the cut's size.
RGB reconstruction_cut(const Scene& scene, const PointLightSet& set,
                       const ManyLightSettings& settings, const LightTree& tree,
                       const GatherPoint& g, int k, std::span<const SparseCut* const> corners,
                       int* nodes);

}  // namespace ml
