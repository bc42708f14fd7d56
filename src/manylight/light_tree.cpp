#include "manylight/light_tree.h"
#include "manylight/vpl_memory.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "manylight/representative.h"

namespace ml {

float light_cluster_metric(float luminance, const Bounds3& b, float cone_theta, float c,
                           bool no_box) {
    float alpha2 = no_box || b.empty() ? 0.f : length_squared(b.diagonal());
    float one_minus_cos = 2 * sqr(std::sin(cone_theta / 2));  // 1 - cos, without cancellation
    return luminance * (alpha2 + c * c * sqr(one_minus_cos));
}

namespace {

// Spreads the low 21 bits of v to every third bit.
uint64_t spread_bits_21(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

// 63-bit Morton code of a point with coordinates in [0, 1].
uint64_t morton_code(const Vec3& u) {
    auto q = [](float x) { return uint64_t(std::clamp(x, 0.f, 1.f) * float((1 << 21) - 1)); };
    return spread_bits_21(q(u.x)) << 2 | spread_bits_21(q(u.y)) << 1 | spread_bits_21(q(u.z));
}

// acos to about 7e-5 rad (Abramowitz & Stegun 4.4.45), for the metric only: it steers the
// clustering, while the nodes' cones are computed exactly (union_cones). The metric's trig
// dominated the build before.
inline float fast_acos(float x) {
    float ax = std::min(std::abs(x), 1.f);
    float r =
        std::sqrt(1 - ax) * (1.5707288f + ax * (-0.2121144f + ax * (0.0742610f - 0.0187293f * ax)));
    return x < 0 ? kPi - r : r;
}

// 1 - cos(beta) = 2 sin^2(beta / 2) for beta in [0, pi], by a Taylor polynomial of sin on
// [0, pi / 2] (error below 2e-4, relative error far smaller for small beta).
inline float one_minus_cos(float beta) {
    float x = beta / 2, x2 = x * x;
    float s = x * (1 + x2 * (-1.f / 6 + x2 * (1.f / 120 - x2 * (1.f / 5040))));
    return 2 * s * s;
}

// The clusters still to be merged, in Morton order, with what the metric needs of each, kept
// contiguous so that the window search streams through memory.
struct Clusters {
    std::vector<int32_t> node;
    std::vector<Bounds3> box;
    std::vector<Vec3> axis;
    std::vector<float> theta;  // padded half-angle of the cone
    std::vector<float> lum;

    void resize(size_t n) {
        node.resize(n);
        box.resize(n);
        axis.resize(n);
        theta.resize(n);
        lum.resize(n);
    }
    size_t size() const { return node.size(); }
};

// The metric of the union of clusters i and j; the arguments are always given in index order so
// that the cost is exactly symmetric (float addition is not associative), which PLOC's
// mutual-best-pair test relies on to terminate.
struct PairCost {
    const Clusters* cl;
    float c2;
    bool use_box, use_cone;

    float operator()(size_t i, size_t j) const {
        float cost = 0;
        if (use_box) {
            Vec3 lo = vmin(cl->box[i].lo, cl->box[j].lo), hi = vmax(cl->box[i].hi, cl->box[j].hi);
            cost = length_squared(hi - lo);
        }
        if (use_cone) {
            float ta = cl->theta[i], tb = cl->theta[j];
            float td = fast_acos(dot(cl->axis[i], cl->axis[j]));
            float beta;
            if (td + tb <= ta)
                beta = ta;
            else if (td + ta <= tb)
                beta = tb;
            else
                beta = std::min(kPi, (ta + td + tb) / 2);
            cost += c2 * sqr(one_minus_cos(beta));
        }
        return (cl->lum[i] + cl->lum[j]) * cost;
    }
};

// A node while the tree is built, every field but the representatives together (lay_out splits
// them into the hot nodes and the side arrays).
struct BuildNode {
    Bounds3 bounds;
    DirectionCone cone;
    RGB intensity;
    float weight = 0;
    RGB bound_intensity;
    int32_t children[2] = {-1, -1};
    PointLightKind kind = PointLightKind::Omni;
    int32_t clampable = 0;
    uint8_t falloff[kFalloffBins] = {};

    bool is_leaf() const { return children[0] < 0; }
};

}  // namespace

namespace detail {
struct LightTreeBuild {
    std::vector<BuildNode> nodes;
    std::vector<int32_t> reps;  // `rep_count` per node
    size_t rep_count = kLightTreeReps;
    std::vector<RGB> chroma;  // per node: its lights' largest I_c / w_i
};
}  // namespace detail

namespace {

int32_t build_kind(detail::LightTreeBuild& build, const std::vector<PointLight>& lights,
                   PointLightKind kind, const LightTreeOptions& opts) {
    const bool directional = kind == PointLightKind::Directional;
    const bool has_cone = kind != PointLightKind::Omni;

    // 1. The lights of this kind, their bounds, and their Morton codes (position; direction for
    //    directional lights).
    std::vector<int32_t> ids;
    Bounds3 all;
    for (size_t i = 0; i < lights.size(); ++i)
        if (lights[i].kind == kind) {
            ids.push_back(int32_t(i));
            all.expand(lights[i].p);
        }
    if (ids.empty()) return -1;
    size_t n = ids.size();
    float c = 0;
    // Walter et al. weigh the cone's angle by half the scene's size (seed 004: "half the
    // scene's bbox"); a full diagonal mixes orientations less and makes kitchen cuts 3% larger.
    if (kind == PointLightKind::Oriented || kind == PointLightKind::Glossy)
        c = 0.5f * (opts.scene_diagonal > 0 ? opts.scene_diagonal : length(all.diagonal()));
    if (directional) c = 1;

    Vec3 extent = all.diagonal();
    auto unit = [&](float x, float lo, float e) { return e > 0 ? (x - lo) / e : 0.5f; };
    std::vector<std::pair<uint64_t, int32_t>> keys(n);
    parallel_for(size_t(0), n, [&](size_t k) {
        const PointLight& pl = lights[size_t(ids[k])];
        Vec3 u = directional
                     ? (pl.n + Vec3(1, 1, 1)) * 0.5f
                     : Vec3(unit(pl.p.x, all.lo.x, extent.x), unit(pl.p.y, all.lo.y, extent.y),
                            unit(pl.p.z, all.lo.z, extent.z));
        uint64_t code = morton_code(u);
        if (kind == PointLightKind::Oriented || kind == PointLightKind::Glossy) {
            // Lights facing different ways rarely belong together (the metric's orientation
            // term, with c the scene's diagonal, outweighs distance), but Morton order by
            // position alone puts a corner's two walls side by side. Leading bits for the
            // normal's dominant axis and sign keep the window search among like-facing lights.
            Vec3 a = vabs(pl.n);
            int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
            uint64_t bin = uint64_t(2 * axis + (pl.n[axis] < 0 ? 1 : 0));
            code = bin << 60 | code >> 3;
        }
        keys[k] = {code, ids[k]};
    });
    parallel_sort(keys.begin(), keys.end());

    // 2. One leaf per light, in Morton order.
    const size_t base = build.nodes.size();
    build.nodes.resize(base + n);
    build.reps.resize(build.nodes.size() * build.rep_count);
    build.chroma.resize(build.nodes.size());
    Clusters cl;
    cl.resize(n);
    parallel_for(size_t(0), n, [&](size_t k) {
        const PointLight& pl = lights[size_t(keys[k].second)];
        BuildNode& node = build.nodes[base + k];
        node.kind = kind;
        // A leaf's representatives are all its light.
        std::fill_n(build.reps.begin() + ptrdiff_t((base + k) * build.rep_count), build.rep_count,
                    keys[k].second);
        node.intensity = pl.intensity;
        node.weight = selection_weight(pl.intensity);
        node.bound_intensity = pl.intensity;  // the light's own value is exact
        RGB& chroma = build.chroma[base + k];
        for (int c = 0; c < 3; ++c)
            chroma[c] = node.weight > 0 ? pl.intensity[c] / node.weight : 0.f;
        node.clampable = pl.is_vpl ? 1 : 0;
        std::copy_n(pl.falloff, kFalloffBins, node.falloff);
        if (!directional) node.bounds.expand(pl.p);
        node.cone = has_cone ? DirectionCone(normalize(pl.n)) : DirectionCone::entire_sphere();
        cl.node[k] = int32_t(base + k);
        cl.box[k] = node.bounds;
        cl.axis[k] = node.cone.axis;
        cl.theta[k] = cone_angle(node.cone);
        cl.lum[k] = node.weight;
    });

    // 3. PLOC: every cluster finds its best partner within the window; mutual best pairs merge
    //    into a new node at the lower position; repeat until one cluster is left.
    const size_t r = size_t(std::max(1, opts.window_radius));
    PairCost cost{&cl, c * c, !directional, has_cone};
    std::vector<float> costs;  // costs[i * r + k]: cost of (i, i + 1 + k)
    std::vector<int32_t> best;
    std::vector<int32_t> new_id;  // per position: the new node's offset (merges), else -1
    Clusters next;
    while (cl.size() > 1) {
        size_t m = cl.size();
        costs.resize(m * r);  // only the pairs inside [0, m) are written and read
        parallel_for(size_t(0), m, [&](size_t i) {
            for (size_t k = 0; k < r && i + 1 + k < m; ++k) costs[i * r + k] = cost(i, i + 1 + k);
        });
        best.assign(m, -1);
        parallel_for(size_t(0), m, [&](size_t i) {
            // Ascending j with a strict comparison: ties go to the smaller index, which keeps the
            // global best pair mutual.
            float bc = kInfinity;
            int32_t bj = -1;
            for (size_t k = std::min(r, i); k >= 1; --k) {
                float v = costs[(i - k) * r + (k - 1)];
                if (v < bc || bj < 0) bc = v, bj = int32_t(i - k);
            }
            for (size_t k = 0; k < r && i + 1 + k < m; ++k) {
                float v = costs[i * r + k];
                if (v < bc || bj < 0) bc = v, bj = int32_t(i + 1 + k);
            }
            best[i] = bj;
        });

        // Number the merges in position order (deterministic) and lay out the next clusters.
        new_id.assign(m, -1);
        size_t merges = 0, kept = 0;
        std::vector<int32_t> next_pos(m, -1);
        for (size_t i = 0; i < m; ++i) {
            size_t j = size_t(best[i]);
            bool mutual = size_t(best[j]) == i;
            if (mutual && j < i) continue;  // absorbed by its partner
            if (mutual) new_id[i] = int32_t(merges++);
            next_pos[i] = int32_t(kept++);
        }
        if (merges == 0) {
            // Cannot happen with an exactly symmetric cost; merge the first two rather than loop.
            best[0] = 1, best[1] = 0, new_id.assign(m, -1), new_id[0] = 0, merges = 1;
            kept = 0;
            for (size_t i = 0; i < m; ++i) next_pos[i] = i == 1 ? -1 : int32_t(kept++);
        }

        size_t first_new = build.nodes.size();
        build.nodes.resize(first_new + merges);
        build.reps.resize(build.nodes.size() * build.rep_count);
        build.chroma.resize(build.nodes.size());
        next.resize(kept);
        parallel_for(size_t(0), m, [&](size_t i) {
            if (next_pos[i] < 0) return;
            size_t p = size_t(next_pos[i]);
            if (new_id[i] < 0) {
                next.node[p] = cl.node[i], next.box[p] = cl.box[i], next.axis[p] = cl.axis[i];
                next.theta[p] = cl.theta[i], next.lum[p] = cl.lum[i];
                return;
            }
            size_t id = first_new + size_t(new_id[i]);
            int32_t a = cl.node[i], b = cl.node[size_t(best[i])];
            const BuildNode &na = build.nodes[size_t(a)], &nb = build.nodes[size_t(b)];
            BuildNode node;
            node.kind = kind;
            node.children[0] = a, node.children[1] = b;
            node.intensity = na.intensity + nb.intensity;
            node.weight = na.weight + nb.weight;
            // Every light's I_c / w_i is at most the node's chroma_c, so both the sum of the
            // intensities and any representative's I_rep weight / w_rep are at most weight
            // chroma_c; the margin covers float rounding in the estimate and the bound.
            RGB& chroma = build.chroma[id];
            chroma = RGB(std::max(build.chroma[size_t(a)].r, build.chroma[size_t(b)].r),
                         std::max(build.chroma[size_t(a)].g, build.chroma[size_t(b)].g),
                         std::max(build.chroma[size_t(a)].b, build.chroma[size_t(b)].b));
            for (int c = 0; c < 3; ++c)
                node.bound_intensity[c] =
                    std::max(node.intensity[c], node.weight * chroma[c] * (1 + 1e-5f));
            // Either child holding a light that is not a VPL makes the sum not clampable (-1).
            node.clampable =
                (na.clampable > 0 && nb.clampable > 0) ? na.clampable + nb.clampable : -1;
            node.bounds = na.bounds;
            node.bounds.expand(nb.bounds);
            node.cone = has_cone ? union_cones(na.cone, nb.cone) : DirectionCone::entire_sphere();
            // Bin by bin the largest falloff (smallest q): the estimate, the representative's
            // value scaled by the node's intensity, then never exceeds the node's bound.
            for (int j = 0; j < kFalloffBins; ++j)
                node.falloff[j] = std::min(na.falloff[j], nb.falloff[j]);
            // Representative: a child's, with probability proportional to its weight. Along the
            // path from the root to a light the probabilities multiply to w_i / weight, with the
            // very weights stored in the nodes, which the estimate's scale uses.
            Rng rng(hash_ints(opts.seed, uint64_t(kind), id));
            float u = rng.next_float();
            int32_t* reps = &build.reps[id * build.rep_count];
            for (size_t k = 0; k < build.rep_count; ++k) {
                if (k > 0) u = rng.next_float();
                bool pick_a = node.weight > 0 ? u * node.weight < na.weight : u < 0.5f;
                reps[k] = build.reps[size_t(pick_a ? a : b) * build.rep_count + k];
            }
            build.nodes[id] = node;
            next.node[p] = int32_t(id), next.box[p] = node.bounds, next.axis[p] = node.cone.axis;
            next.theta[p] = cone_angle(node.cone), next.lum[p] = node.weight;
        });
        std::swap(cl, next);
    }
    return cl.node[0];
}

}  // namespace

LightTree::LightTree(const std::vector<PointLight>& lights, const LightTreeOptions& opts)
    : m_light_count(lights.size()) {
    // A binary tree over n leaves has 2n - 1 nodes: reserve them all so that no build step
    // reallocates under parallel writers.
    if (opts.reps < 1 || opts.reps > kLightTreeMaxReps)
        throw UsageError(
            fmt::format("tree.reps must be 1 to {}, not {}", kLightTreeMaxReps, opts.reps));
    m_rep_count = opts.reps;
    detail::LightTreeBuild build;
    build.rep_count = size_t(opts.reps);
    build.nodes.reserve(2 * lights.size());
    for (PointLightKind kind : kAllPointLightKinds)
        m_roots[int(kind)] = build_kind(build, lights, kind, opts);
    lay_out(build);
}

// Cuts are refined from the roots down, so nodes laid out depth-first, each pair of children
// side by side, are read from memory mostly in order rather than all over a large array. The
// built nodes split here into the hot nodes and the side arrays.
void LightTree::lay_out(detail::LightTreeBuild& build) {
    const std::vector<BuildNode>& built = build.nodes;
    // 1. The order: the old index of each new node, and each new node's first child.
    std::vector<int32_t> old_of_new, first_child;
    old_of_new.reserve(built.size());
    first_child.reserve(built.size());
    std::vector<std::pair<int32_t, int32_t>> stack;  // (old index, new index already taken)
    for (int32_t& root : m_roots) {
        if (root < 0) continue;
        old_of_new.push_back(root);
        first_child.push_back(-1);
        int32_t new_root = int32_t(old_of_new.size() - 1);
        stack.push_back({root, new_root});
        root = new_root;
        while (!stack.empty()) {
            auto [old_index, new_index] = stack.back();
            stack.pop_back();
            const BuildNode& old_node = built[size_t(old_index)];
            if (old_node.is_leaf()) continue;
            int32_t first = int32_t(old_of_new.size());
            for (int k = 0; k < 2; ++k) {
                old_of_new.push_back(old_node.children[k]);
                first_child.push_back(-1);
            }
            first_child[size_t(new_index)] = first;
            for (int k = 0; k < 2; ++k) stack.push_back({old_node.children[k], first + k});
        }
    }
    // 2. The hot nodes and the side arrays in that order.
    const size_t n = old_of_new.size();
    m_nodes.resize(n);
    m_reps.resize(n * build.rep_count);
    m_weight.resize(n);
    m_intensity.resize(n);
    m_falloff.resize(n);
    parallel_for(size_t(0), n, [&](size_t i) {
        size_t old = size_t(old_of_new[i]);
        const BuildNode& b = built[old];
        LightTreeNode& hot = m_nodes[i];
        hot.bounds = b.bounds;
        hot.cone = b.cone;
        hot.bound_intensity = b.bound_intensity;
        hot.first_child = first_child[i];
        hot.clampable = b.clampable;
        hot.kind = b.kind;
        for (size_t k = 0; k < build.rep_count; ++k)
            m_reps[i * build.rep_count + k] = build.reps[old * build.rep_count + k];
        m_weight[i] = b.weight;
        m_intensity[i] = b.intensity;
        std::copy_n(b.falloff, kFalloffBins, m_falloff[i].begin());
    });
}

size_t light_tree_bytes_per_light(int reps) {
    return 2 * (sizeof(LightTreeNode) + size_t(reps) * sizeof(int32_t) + sizeof(float) +
                sizeof(RGB) + kFalloffBins);
}

size_t light_tree_peak_build_bytes_per_light(int reps) {
    // The built nodes with their representatives and chroma, alive throughout; while the lights
    // are clustered, per light its id, its Morton key, two sets of clusters' columns and PLOC's
    // window of costs and its indices; then, while the nodes are laid out, the tree and two
    // indices per node.
    const size_t built = 2 * (sizeof(BuildNode) + size_t(reps) * sizeof(int32_t) + sizeof(RGB));
    const size_t clustering =
        sizeof(int32_t) + sizeof(std::pair<uint64_t, int32_t>) +
        2 * (sizeof(int32_t) + sizeof(Bounds3) + sizeof(Vec3) + 2 * sizeof(float)) +
        size_t(LightTreeOptions{}.window_radius) * sizeof(float) + 3 * sizeof(int32_t);
    const size_t laying_out = light_tree_bytes_per_light(reps) + 2 * 2 * sizeof(int32_t);
    return built + std::max(clustering, laying_out);
}

}  // namespace ml
