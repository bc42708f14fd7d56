// Path guiding's spatio-directional tree (after Müller, Gross and Novák, "Practical Path
// Guiding", 2017): a binary tree over the scene's bounds whose leaves (regions) each hold a
// quadtree over the sphere of directions, in the cylindrical map (cos theta, phi) that keeps
// areas. Each quadtree's leaves hold the energy (incident radiance over the density it was
// sampled with) that paths recorded there, so that sampling a leaf by its energy share follows
// the light arriving at the region.
//
// Training runs in passes. During a pass the regions' `distribution` (learned in the last pass)
// guides while the paths record into `training`, a quadtree of its own shape; the records are
// fixed-point integers added atomically, so the sums do not depend on the order in which
// threads add them. After the pass, refine() makes the trained quadtrees the distributions,
// splits regions that received many records, and shapes the new training quadtrees by the
// energy they learned.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/math.h"

namespace ml {

// The cylindrical map between directions and the unit square: (cos theta + 1) / 2 and
// phi / 2 pi, world-space z up. Its Jacobian is constant: a density p over the square is
// p / (4 pi) over solid angle.
Vec2 direction_to_square(const Vec3& w);
Vec3 square_to_direction(const Vec2& u);

// A quadtree over the unit square: each node splits its square into four quadrants
// (index x + 2 y, x and y the halves), each either a leaf or a child node, with the energy
// found in it.
class DirectionTree {
public:
    DirectionTree();  // the root's four quadrants, leaves without energy
    double total() const;
    size_t nodes() const { return m_nodes.size(); }

    // A direction with density pdf_solid_angle(); the tree must have energy.
    Vec3 sample(const Vec2& u) const;
    // The density over solid angle of sample(); 0 everywhere for a tree without energy.
    float pdf_solid_angle(const Vec3& w) const;

    // The quadtree for the next pass's training: a quadrant is split where it holds more than
    // `share` of the total energy and at least `min_records` records (a leaf's energy and
    // records taken as spread evenly over it), up to `max_depth` levels; without energy, this
    // tree's own shape. Energies are zero.
    DirectionTree refined(double share, int max_depth, double min_records = 0) const;
    // The index of the leaf slot (node * 4 + quadrant) holding direction w.
    uint32_t leaf_slot(const Vec3& w) const;
    // Sets the leaf slots' energies (one per slot, inner slots ignored) and, when given, their
    // record counts (else as many as any refinement asks for), and sums them up into the inner
    // slots.
    void set_energies(const std::vector<double>& slots,
                      const std::vector<double>* records = nullptr);

private:
    struct Node {
        uint32_t child[4] = {0, 0, 0, 0};  // 0: the quadrant is a leaf (the root is never a child)
        double energy[4] = {0, 0, 0, 0};
        double records[4] = {0, 0, 0, 0};  // how many records the energy is the sum of
    };
    std::vector<Node> m_nodes;
};

class SDTree {
public:
    // Müller's constants: a region splits once it received more than
    // kSpatialThreshold * sqrt(paths / kReferencePaths) records, `paths` those the pass traced;
    // a quadrant splits above kEnergyShare of the energy, up to kMaxQuadtreeDepth levels, once
    // it has kMinSplitRecords records.
    // Müller's threshold, 12000 sqrt(2^pass), is for passes of 4 * 2^pass samples per pixel at
    // 1280x720: scaled by the paths of the pass instead, a small image (a test's, a preview)
    // still splits its scene into regions, each learning from about as many records as the
    // square root of the pass's paths (at 32x32 and one sample per pixel: about 200).
    static constexpr double kSpatialThreshold = 12000;
    static constexpr double kReferencePaths = 4.0 * 1280 * 720;
    static constexpr double kEnergyShare = 0.01;
    // A quadrant splits only once it received this many records (ours, not Müller's): split by
    // energy alone, a region's first few records towards a small bright source made leaves
    // finer than the records, and the guide holes that later passes, sampling by it, never
    // filled (bench/RESULTS.md, "Path guiding").
    static constexpr double kMinSplitRecords = 256;
    static constexpr int kMaxQuadtreeDepth = 20;

    explicit SDTree(const Bounds3& bounds);
    ~SDTree();

    struct Region;
    // The region holding p (points outside the bounds: the nearest).
    const Region* region(const Vec3& p) const;
    // The region's learned distribution, or null where it has learned nothing.
    static const DirectionTree* distribution(const Region* region);
    // Adds a record: `energy` (incident radiance along w over the density w was sampled with)
    // into the region's training quadtree. Thread-safe, and the sums are exact (fixed-point).
    static void record(const Region* region, const Vec3& w, double energy);
    // The end of a pass that traced `paths` paths: see the header comment.
    void refine(double paths);
    size_t regions() const { return m_regions.size(); }

private:
    struct Node {
        int axis = -1;  // -1: a leaf, holding region `region`; else split at the middle
        uint32_t child[2] = {0, 0};
        uint32_t region = 0;
    };
    void split(uint32_t node, const Bounds3& bounds, int depth, double threshold);

    Bounds3 m_bounds;
    std::vector<Node> m_nodes;
    std::vector<std::unique_ptr<Region>> m_regions;
};

}  // namespace ml
