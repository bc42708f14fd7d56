// The primary-sample-space sampler of Kelemen et al. 2002: a path is a point of the unit
// hypercube, extended lazily one dimension at a time, and a Markov chain moves that point by
// small steps (a normal perturbation of every coordinate, wrapped around [0,1)) or large steps
// (every coordinate drawn afresh). A rejected proposal restores exactly the coordinates it
// changed.
//
// Coordinates are read in streams (`start_stream(i)`): stream i owns the dimensions
// i, i + n, i + 2n, ... of n streams, so a bidirectional estimator that draws a variable number of
// camera samples never shifts the light subpath's coordinates.
//
// Mutations are applied lazily: a coordinate untouched for k small steps receives one normal step
// of standard deviation sigma * sqrt(k) when next read, which has the distribution of k steps;
// one untouched since a large step is redrawn when read.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "sampling/sampler.h"

namespace ml {

// The standard normal quantile: the x with Phi(x) = u, for u in (0, 1) (clamped into it).
double standard_normal_quantile(double u);

// A generator's whole state as two words and back, to save and restore it exactly (checkpoints).
std::array<uint64_t, 2> rng_state(const Rng& rng);
void set_rng_state(Rng& rng, const std::array<uint64_t, 2>& state);

class MltSampler final : public Sampler {
public:
    // `seed` and `index` choose the random sequence: a sampler made with the same pair
    // reproduces the same primary samples, which is how a chain restarts a bootstrap path.
    MltSampler(uint64_t seed, uint64_t index, float sigma, float large_step_prob, int stream_count,
               int mutations_per_pixel = 1);

    // Begins a proposal: a large step with probability large_step_prob, else a small one.
    void start_iteration();
    // Keeps the proposal as the chain's state.
    void accept();
    // Drops the proposal: every coordinate it touched gets its old value back.
    void reject();
    bool is_large_step() const { return m_large_step; }

    // Reads from stream `index` (< stream_count), from its first coordinate.
    void start_stream(int index);

    // Sampler: start_pixel_sample() restarts stream 0 at `dimension` (the chain, not the pixel,
    // chooses where a path goes); get_pixel_2d() is get_2d().
    int samples_per_pixel() const override { return m_mutations_per_pixel; }
    void start_pixel_sample(Point2i pixel, int index, int dimension) override;
    float get_1d() override;
    Vec2 get_2d() override;
    std::unique_ptr<Sampler> clone() const override;
    std::string name() const override { return "pssmlt"; }

    // The state, for tests: coordinates made so far (in interleaved order) and one of them.
    size_t dimension_count() const { return m_x.size(); }
    float value(size_t i) const { return m_x[i].value; }
    int64_t iteration() const { return m_iteration; }

    // The chain's whole state (numbers, backups, iteration), to continue exactly elsewhere
    // (checkpoints); restore() takes what state() gave a sampler made with the same parameters.
    nlohmann::json state() const;
    void restore(const nlohmann::json& state);

private:
    struct PrimarySample {
        float value = 0, value_backup = 0;
        int64_t last_modified = -1, modified_backup = -1;  // iteration of the last change
    };
    // Brings coordinate `i` up to the current iteration (creating it if needed).
    void ensure_ready(size_t i);

    Rng m_rng;
    float m_sigma, m_large_step_prob;
    int m_stream_count, m_mutations_per_pixel;
    std::vector<PrimarySample> m_x;
    int64_t m_iteration = 0;
    int64_t m_last_large_step = 0;
    bool m_large_step = true;  // the first evaluation draws every coordinate uniformly
    int m_stream = 0;
    int64_t m_stream_sample = 0;
};

}  // namespace ml
