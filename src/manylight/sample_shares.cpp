#include "manylight/sample_shares.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/world.h"
#include "render/checkpoint.h"

namespace ml {

std::vector<float> neighbour_sample_shares(int width, int height,
                                           const std::vector<float>& relative_variance) {
    const size_t n = size_t(std::max(0, width)) * size_t(std::max(0, height));
    std::vector<float> share(n, 1.f);
    if (n == 0 || relative_variance.size() != n) return share;
    double total = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double sum = 0;
            int count = 0;
            for (int yy = std::max(0, y - kShareRadius);
                 yy <= std::min(height - 1, y + kShareRadius); ++yy)
                for (int xx = std::max(0, x - kShareRadius);
                     xx <= std::min(width - 1, x + kShareRadius); ++xx) {
                    if (xx == x && yy == y) continue;
                    const float v = relative_variance[size_t(yy) * size_t(width) + size_t(xx)];
                    sum += std::isfinite(v) && v > 0 ? double(v) : 0.0;
                    ++count;
                }
            const double s = count > 0 ? std::sqrt(sum / count) : 0.0;
            share[size_t(y) * size_t(width) + size_t(x)] = float(s);
            total += s;
        }
    const double mean = total / double(n);
    if (!(mean > 0)) {
        std::fill(share.begin(), share.end(), 1.f);
        return share;
    }
    double clamped = 0;
    for (float& s : share) {
        s = std::clamp(float(double(s) / mean), kMinSampleShare, kMaxSampleShare);
        clamped += s;
    }
    const float scale = float(double(n) / clamped);
    for (float& s : share) s *= scale;
    return share;
}

SamplePasses render_adaptive_passes(
    const RenderContext& ctx, int pass_samples, double fixed_share,
    const std::function<float(Point2i pixel, int first, int samples)>& fn,
    const std::function<void(const LastPass& plan)>& last, float* max_share,
    const std::function<void(int64_t pass)>& begin_pass) {
    const int w = ctx.film.width(), h = ctx.film.height();
    const size_t n = size_t(w) * size_t(h);
    std::vector<float> variance(n, 0.f), shares(n, 1.f);
    std::vector<int> next(n, 0);
    auto pass = [&](Point2i pixel, int first, int samples) {
        const size_t i = size_t(pixel.y) * size_t(w) + size_t(pixel.x);
        if (first == 0) {
            variance[i] = fn(pixel, 0, samples);
            next[i] = samples;
            return;
        }
        const int parts = std::max(1, int(std::lround(shares[i])));
        const int each = std::max(1, int(std::lround(float(samples) * shares[i] / float(parts))));
        for (int part = 0; part < parts; ++part) {
            fn(pixel, next[i], each);
            next[i] += each;
        }
    };
    auto plan = [&] {
        // (A copy: `variance` stays this rank's own, as a checkpoint saves it.)
        std::vector<float> all = variance;
        if (ctx.ranks() > 1) {
            // Each pixel's variance is non-zero on the rank that owns it alone: exact sums.
            ctx.world->reduce_sum(all.data(), n);
            ctx.world->broadcast(all.data(), n * sizeof(float));
        }
        shares = neighbour_sample_shares(w, h, all);
        if (max_share && !shares.empty())
            *max_share = *std::max_element(shares.begin(), shares.end());
    };
    // With a checkpoint, the first pass's variances and each pixel's next sample go into its
    // state: the shares follow from the variances exactly (plan() runs again on resuming), and
    // the pixels a stop left ahead have theirs.
    Checkpoint* checkpoint = ctx.checkpoint;
    if (!checkpoint)
        return render_sample_passes(ctx, pass_samples, fixed_share, pass, last, plan, begin_pass);
    if (checkpoint->resuming()) {
        const nlohmann::json& state = checkpoint->integrator_state();
        if (!state.contains("adaptive"))
            throw UsageError("--resume: the checkpoint holds no adaptive sampling state");
        try {
            variance = from_binary<float>(state["adaptive"].at("variance"), n);
            next = from_binary<int>(state["adaptive"].at("next"), n);
        } catch (const std::exception& e) {
            throw UsageError(std::string("--resume: a damaged checkpoint (") + e.what() + ")");
        }
    }
    const std::function<nlohmann::json()> outer = checkpoint->state();
    checkpoint->set_state([&] {
        nlohmann::json j = outer ? outer() : nlohmann::json::object();
        j["adaptive"] = {{"variance", to_binary(variance)}, {"next", to_binary(next)}};
        return j;
    });
    SamplePasses out =
        render_sample_passes(ctx, pass_samples, fixed_share, pass, last, plan, begin_pass);
    checkpoint->set_state(outer);
    return out;
}

}  // namespace ml
