#include "transport/sd_tree.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"

namespace ml {

namespace {

// Records are added as integers of 2^-24 units: the sums are then the same in any order. One
// record is clamped to kMaxRecord, which leaves room for 5e4 such records in a slot.
constexpr double kFixedScale = 16777216.0;
constexpr double kMaxRecord = 1e7;

double clamp_unit(double u) { return std::min(std::max(u, 0.0), 0x1.fffffffffffffp-1); }

void set_axis(Vec3& v, int axis, float value) { (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = value; }

}  // namespace

Vec2 direction_to_square(const Vec3& w) {
    float cos_theta = std::clamp(w.z, -1.f, 1.f);
    float phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * kPi;
    return Vec2(std::clamp((cos_theta + 1) * 0.5f, 0.f, 1.f),
                std::clamp(phi * (0.5f * kInvPi), 0.f, 1.f));
}

Vec3 square_to_direction(const Vec2& u) {
    float cos_theta = 2 * u.x - 1;
    float sin_theta = safe_sqrt(1 - cos_theta * cos_theta);
    float phi = 2 * kPi * u.y;
    return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

// DirectionTree ---------------------------------------------------------------------------------

DirectionTree::DirectionTree() : m_nodes(1) {}

double DirectionTree::total() const {
    const Node& root = m_nodes[0];
    return root.energy[0] + root.energy[1] + root.energy[2] + root.energy[3];
}

Vec3 DirectionTree::sample(const Vec2& u_in) const {
    double u = clamp_unit(u_in.x), v = clamp_unit(u_in.y);
    double ox = 0, oy = 0, size = 1;
    uint32_t n = 0;
    for (;;) {
        const Node& node = m_nodes[n];
        const double* e = node.energy;
        // The column (x half) by its energy, then the row within it: quadrant x + 2 y.
        const double left = e[0] + e[2], all = left + e[1] + e[3];
        ML_ASSERT(all > 0, "sampling a direction tree without energy");
        const double p_left = left / all;
        int x = u < p_left ? 0 : 1;
        u = clamp_unit(x == 0 ? u / p_left : (u - p_left) / (1 - p_left));
        const double column = e[x] + e[x + 2], p_low = e[x] / column;
        int y = v < p_low ? 0 : 1;
        v = clamp_unit(y == 0 ? v / p_low : (v - p_low) / (1 - p_low));
        size *= 0.5;
        ox += x * size;
        oy += y * size;
        const uint32_t c = node.child[x + 2 * y];
        if (c == 0) break;
        n = c;
    }
    return square_to_direction(Vec2(float(ox + u * size), float(oy + v * size)));
}

float DirectionTree::pdf_solid_angle(const Vec3& w) const {
    const Vec2 s = direction_to_square(w);
    double u = s.x, v = s.y, pdf = 1;
    uint32_t n = 0;
    for (;;) {
        const Node& node = m_nodes[n];
        const double all = node.energy[0] + node.energy[1] + node.energy[2] + node.energy[3];
        if (all <= 0) return 0;
        const int x = u < 0.5 ? 0 : 1, y = v < 0.5 ? 0 : 1, q = x + 2 * y;
        pdf *= 4 * node.energy[q] / all;
        if (node.child[q] == 0 || pdf == 0) break;
        u = 2 * u - x;
        v = 2 * v - y;
        n = node.child[q];
    }
    return float(pdf * kInv4Pi);
}

uint32_t DirectionTree::leaf_slot(const Vec3& w) const {
    const Vec2 s = direction_to_square(w);
    double u = s.x, v = s.y;
    uint32_t n = 0;
    for (;;) {
        const int x = u < 0.5 ? 0 : 1, y = v < 0.5 ? 0 : 1, q = x + 2 * y;
        const uint32_t c = m_nodes[n].child[q];
        if (c == 0) return n * 4 + uint32_t(q);
        u = 2 * u - x;
        v = 2 * v - y;
        n = c;
    }
}

void DirectionTree::set_energies(const std::vector<double>& slots,
                                 const std::vector<double>* records) {
    ML_ASSERT(slots.size() == 4 * m_nodes.size(), "one energy per quadrant");
    ML_ASSERT(!records || records->size() == slots.size(), "one record count per quadrant");
    // Children come after their parents: sum from the last node up.
    for (size_t i = m_nodes.size(); i-- > 0;) {
        Node& node = m_nodes[i];
        for (int q = 0; q < 4; ++q) {
            const uint32_t c = node.child[q];
            if (c == 0) {
                node.energy[q] = slots[4 * i + size_t(q)];
                node.records[q] = records ? (*records)[4 * i + size_t(q)] : kInfinity;
            } else {
                const Node& child = m_nodes[c];
                node.energy[q] =
                    child.energy[0] + child.energy[1] + child.energy[2] + child.energy[3];
                node.records[q] =
                    child.records[0] + child.records[1] + child.records[2] + child.records[3];
            }
        }
    }
}

DirectionTree DirectionTree::refined(double share, int max_depth, double min_records) const {
    const double all = total();
    DirectionTree out;
    if (!(all > 0)) {
        out.m_nodes = m_nodes;
        for (Node& node : out.m_nodes) std::fill(std::begin(node.energy), std::end(node.energy), 0);
        return out;
    }
    // Walk this tree and the new one together; a quadrant this tree has as a leaf spreads its
    // energy evenly over the quadrants it splits into.
    struct Item {
        uint32_t out_node;
        int64_t src_node;  // -1: inside a leaf of this tree, of `leaf_energy` and `leaf_records`
        double leaf_energy, leaf_records;
        int depth;
    };
    std::vector<Item> stack{{0, 0, 0, 0, 1}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        for (int q = 0; q < 4; ++q) {
            const Node* src = it.src_node >= 0 ? &m_nodes[size_t(it.src_node)] : nullptr;
            const double e = src ? src->energy[q] : it.leaf_energy / 4;
            const double n = src ? src->records[q] : it.leaf_records / 4;
            if (it.depth >= max_depth || !(e > share * all) || n < min_records) continue;
            const uint32_t c = uint32_t(out.m_nodes.size());
            out.m_nodes.emplace_back();
            out.m_nodes[it.out_node].child[q] = c;
            const uint32_t src_child = it.src_node >= 0 ? m_nodes[size_t(it.src_node)].child[q] : 0;
            stack.push_back({c, src_child != 0 ? int64_t(src_child) : -1, e, n, it.depth + 1});
        }
    }
    return out;
}

// SDTree ----------------------------------------------------------------------------------------

struct SDTree::Region {
    DirectionTree distribution;                      // learned in the last pass: guides this one
    DirectionTree training;                          // the shape this pass records into
    std::unique_ptr<std::atomic<int64_t>[]> slots;   // 4 per training node, fixed-point energy
    std::unique_ptr<std::atomic<int64_t>[]> counts;  // 4 per training node, records
    std::atomic<int64_t> records{0};

    void start_training(DirectionTree shape) {
        training = std::move(shape);
        slots = std::make_unique<std::atomic<int64_t>[]>(4 * training.nodes());
        counts = std::make_unique<std::atomic<int64_t>[]>(4 * training.nodes());
        for (size_t i = 0; i < 4 * training.nodes(); ++i) slots[i] = counts[i] = 0;
        records = 0;
    }
};

SDTree::SDTree(const Bounds3& bounds) {
    // A cube around the scene, a little larger, so that the regions stay near cubes.
    const Vec3 c = bounds.empty() ? Vec3(0, 0, 0) : bounds.center();
    const Vec3 d = bounds.empty() ? Vec3(1, 1, 1) : bounds.diagonal();
    const float half = 0.5f * 1.01f * std::max({d.x, d.y, d.z, 1e-3f});
    m_bounds.lo = c - Vec3(half, half, half);
    m_bounds.hi = c + Vec3(half, half, half);
    m_nodes.emplace_back();
    m_regions.push_back(std::make_unique<Region>());
    m_regions[0]->start_training(DirectionTree());
}

SDTree::~SDTree() = default;

const SDTree::Region* SDTree::region(const Vec3& p) const {
    Bounds3 b = m_bounds;
    uint32_t n = 0;
    while (m_nodes[n].axis >= 0) {
        const int a = m_nodes[n].axis;
        const float mid = 0.5f * (b.lo[a] + b.hi[a]);
        const int side = p[a] < mid ? 0 : 1;
        set_axis(side == 0 ? b.hi : b.lo, a, mid);
        n = m_nodes[n].child[side];
    }
    return m_regions[m_nodes[n].region].get();
}

const DirectionTree* SDTree::distribution(const Region* region) {
    return region->distribution.total() > 0 ? &region->distribution : nullptr;
}

void SDTree::record(const Region* region, const Vec3& w, double energy) {
    Region& r = const_cast<Region&>(*region);  // the atomics are the training's mutable state
    r.records.fetch_add(1, std::memory_order_relaxed);
    const uint32_t slot = r.training.leaf_slot(w);
    r.counts[slot].fetch_add(1, std::memory_order_relaxed);
    if (!(energy > 0)) return;
    const int64_t units = std::llround(std::min(energy, kMaxRecord) * kFixedScale);
    if (units > 0) r.slots[slot].fetch_add(units, std::memory_order_relaxed);
}

void SDTree::split(uint32_t node, const Bounds3& bounds, int depth, double threshold) {
    if (m_nodes[node].axis >= 0) {
        const int a = m_nodes[node].axis;
        const float mid = 0.5f * (bounds.lo[a] + bounds.hi[a]);
        Bounds3 lo = bounds, hi = bounds;
        set_axis(lo.hi, a, mid);
        set_axis(hi.lo, a, mid);
        const uint32_t c0 = m_nodes[node].child[0], c1 = m_nodes[node].child[1];
        split(c0, lo, depth + 1, threshold);
        split(c1, hi, depth + 1, threshold);
        return;
    }
    Region& r = *m_regions[m_nodes[node].region];
    const int64_t records = r.records.load();
    if (double(records) <= threshold) return;
    // Two halves, each with the region's distribution and half its records.
    auto second = std::make_unique<Region>();
    second->distribution = r.distribution;
    second->records = records / 2;
    r.records = records - records / 2;
    const uint32_t first_child = uint32_t(m_nodes.size());
    Node a, b;
    a.region = m_nodes[node].region;
    b.region = uint32_t(m_regions.size());
    m_regions.push_back(std::move(second));
    m_nodes.push_back(a);
    m_nodes.push_back(b);
    m_nodes[node].axis = depth % 3;
    m_nodes[node].child[0] = first_child;
    m_nodes[node].child[1] = first_child + 1;
    split(node, bounds, depth, threshold);
}

void SDTree::refine(double paths) {
    // 1. What each region learned becomes its distribution.
    for (auto& r : m_regions) {
        std::vector<double> energies(4 * r->training.nodes()), counts(energies.size());
        for (size_t i = 0; i < energies.size(); ++i) {
            energies[i] = double(r->slots[i].load()) / kFixedScale;
            counts[i] = double(r->counts[i].load());
        }
        r->training.set_energies(energies, &counts);
        r->distribution = r->training;
    }
    // 2. Regions that received many records split.
    split(0, m_bounds, 0, kSpatialThreshold * std::sqrt(paths / kReferencePaths));
    // 3. The next pass trains quadtrees shaped by the energy learned.
    for (auto& r : m_regions)
        r->start_training(
            r->distribution.refined(kEnergyShare, kMaxQuadtreeDepth, kMinSplitRecords));
}

}  // namespace ml
