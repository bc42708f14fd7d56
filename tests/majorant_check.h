// A check of a medium's majorant segments (Medium::majorants) along random rays: they adjoin,
// cover the stretch that majorant() gives, stay at or below its one bound, and bound the
// medium's extinction at every point tried on them.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/rng.h"
#include "media/medium.h"

namespace ml::test {

// a == b to a relative 1e-4, infinities included.
inline bool same_t(float a, float b) {
    return a == b || std::abs(a - b) <= 1e-4f * (1 + std::abs(b));
}

// Rays from points of [lo, hi] (widened by half its size) in random directions, each with a
// random length. Returns the share of the stretches' length whose segment bound is below the
// one bound (how much the finer bounds save).
inline double expect_majorants_bound(const Medium& m, const Vec3& lo, const Vec3& hi, int rays,
                                     uint64_t seed) {
    Rng rng(seed);
    double below = 0, total = 0;
    int failures = 0;
    for (int r = 0; r < rays && failures < 5; ++r) {
        const Vec3 ext = hi - lo;
        const Vec3 o(lo.x - 0.5f * ext.x + 2 * ext.x * rng.next_float(),
                     lo.y - 0.5f * ext.y + 2 * ext.y * rng.next_float(),
                     lo.z - 0.5f * ext.z + 2 * ext.z * rng.next_float());
        const float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
        const float s = std::sqrt(std::max(0.f, 1 - z * z));
        const Ray ray{o, Vec3(s * std::cos(phi), s * std::sin(phi), z), kInfinity, 0};
        const float tmax = rng.next_float() < 0.3f ? kInfinity : 3 * length(ext) * rng.next_float();
        const std::optional<MajorantSegment> whole = m.majorant(ray, tmax);
        MajorantIterator it = m.majorants(ray, tmax);
        std::optional<MajorantSegment> seg = it.next();
        if (!whole) {
            EXPECT_FALSE(seg) << "a segment where the ray misses the medium";
            continue;
        }
        float t = whole->t0;
        int count = 0;
        for (; seg; seg = it.next(), ++count) {
            EXPECT_TRUE(same_t(seg->t0, t)) << "ray " << r << " segment " << count << ": starts at "
                                            << seg->t0 << ", the last ended at " << t;
            EXPECT_LE(seg->t0, seg->t1);
            EXPECT_LE(seg->sigma_maj, whole->sigma_maj * (1 + 1e-5f));
            for (int k = 0; k < 8; ++k) {
                const float tt = seg->t0 + (seg->t1 - seg->t0) * rng.next_float();
                const MediumProperties mp = m.at(ray.at(tt));
                const float sigma_t = (mp.sigma_a + mp.sigma_s).max_component();
                if (!(sigma_t <= seg->sigma_maj * (1 + 1e-4f) + 1e-6f)) {
                    ++failures;
                    ADD_FAILURE() << "ray " << r << " segment " << count << " [" << seg->t0 << ", "
                                  << seg->t1 << "): extinction " << sigma_t
                                  << " above its majorant " << seg->sigma_maj;
                    break;
                }
            }
            const double len = double(seg->t1 - seg->t0);
            if (std::isfinite(len)) {
                total += len;
                if (seg->sigma_maj < whole->sigma_maj * 0.999f) below += len;
            }
            t = seg->t1;
        }
        EXPECT_GE(count, 1);
        EXPECT_TRUE(same_t(t, whole->t1))
            << "ray " << r << ": the segments end at " << t << ", the stretch at " << whole->t1;
    }
    return total > 0 ? below / total : 0;
}

}  // namespace ml::test
