// Checkpoints: a render's state saved to a file at round boundaries of the render loop, from which
// a later run continues (--checkpoint, --resume). The state is the film's exact sums, the units
// the loop has done (samples per pixel, passes of the many-light integrators, mutations), per
// pixel where a stop left a round part-done, the render time spent, and what the integrator needs
// to go on (splat sums, Markov chains, the first pass's noise for adaptive sampling). The
// file is one CBOR document (nlohmann-json) holding the arrays as raw bytes: lossless. It names
// what it was rendered from (a fingerprint of the scene file, the integrator and its resolved
// settings, resolution, seed, spp, ranks and the program's version); a run whose fingerprint
// differs is refused. Written to a temporary file beside it and renamed, as images are.
// Across MPI ranks each rank saves its own film and progress (rank r > 0 to FILE.rank<r>): every
// pixel's sum goes on exactly as one process's would, so a resumed render is bit for bit the
// uninterrupted one; it must resume with the same number of ranks (part of the fingerprint).
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ml {

class Film;
class World;

// The program version a checkpoint records: a checkpoint from another version is refused.
inline constexpr const char* kCheckpointVersion = "manylight 0.1 checkpoint 1";

// A stable 64-bit hash (FNV-1a) of bytes, as checkpoints fingerprint the scene file's text.
uint64_t fingerprint_hash(const std::string& bytes);

// Doubles, floats and integers as CBOR byte strings (exact) and back; from_binary throws Error
// when the size does not fit `n` elements.
nlohmann::json to_binary(const void* data, size_t bytes);
template <typename T>
nlohmann::json to_binary(const std::vector<T>& v) {
    return to_binary(v.data(), v.size() * sizeof(T));
}
template <typename T>
std::vector<T> from_binary(const nlohmann::json& j, size_t n);

class Checkpoint {
public:
    // Saves to `path` (empty: never) every `every_seconds`, and reads `resume_path` (empty: a
    // fresh render) for `world`'s rank; `fingerprint` names the render (see above). Throws
    // UsageError when the resume file is unreadable, not a checkpoint, or another render's.
    // The film is the one the render adds to: saved from, and restored into when resuming.
    Checkpoint(std::string path, double every_seconds, const std::string& resume_path,
               nlohmann::json fingerprint, Film& film, World& world);

    // Resuming: the loop's units done, the render seconds spent, and the integrator's state.
    bool resuming() const { return m_resumed; }
    int64_t units() const { return m_units; }
    double seconds() const { return m_seconds; }
    const nlohmann::json& integrator_state() const { return m_integrator_state; }
    // Per pixel (row-major), the units done: where a stop (Ctrl-C, the time limit) cut a round
    // short some pixels are ahead of units(). The pixel loops read and update it.
    int64_t pixel_units(size_t pixel) const { return m_pixel_units[pixel]; }
    void set_pixel_units(size_t pixel, int64_t units) { m_pixel_units[pixel] = units; }

    // What the integrator adds to a save (splat sums, chains): set for the time of a render by
    // an integrator with state of its own; null: none.
    void set_state(std::function<nlohmann::json()> state) { m_state = std::move(state); }
    // The state set, for a layer that adds its own to the integrator's (and sets it back).
    const std::function<nlohmann::json()>& state() const { return m_state; }

    // At a round boundary (every pixel at `units`, or ahead per pixel_units): saves if a save is
    // due. Across ranks a collective (rank 0 decides), so every rank calls it at the same
    // boundaries. `elapsed` is the render's seconds so far, earlier runs included.
    void round_done(int64_t units, double elapsed);
    // Saves now (the end of the render, or a stop): every rank calls it.
    void save(int64_t units, double elapsed);
    bool saving() const { return !m_path.empty(); }
    // Saves written so far.
    int saves() const { return m_saves; }

private:
    std::string m_path;
    double m_every;
    nlohmann::json m_fingerprint;
    Film& m_film;
    World& m_world;
    bool m_resumed = false;
    nlohmann::json m_integrator_state;
    int64_t m_units = 0;
    double m_seconds = 0;
    std::vector<int64_t> m_pixel_units;
    std::function<nlohmann::json()> m_state;
    std::chrono::steady_clock::time_point m_last_save = std::chrono::steady_clock::now();
    int m_saves = 0;
};

}  // namespace ml
