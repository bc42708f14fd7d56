#include "render/checkpoint.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/world.h"
#include "film/film.h"

namespace ml {

namespace {

// Rank r > 0 of several keeps its part beside rank 0's file.
std::string rank_path(const std::string& path, const World& world) {
    return world.rank() == 0 ? path : path + ".rank" + std::to_string(world.rank());
}

std::string show(const nlohmann::json& v) {
    return v.is_string() ? v.get<std::string>() : v.dump();
}

}  // namespace

uint64_t fingerprint_hash(const std::string& bytes) {
    uint64_t h = 0xcbf29ce484222325ULL;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ULL;
    }
    return h;
}

nlohmann::json to_binary(const void* data, size_t bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    return nlohmann::json::binary(std::vector<uint8_t>(p, p + bytes));
}

template <typename T>
std::vector<T> from_binary(const nlohmann::json& j, size_t n) {
    if (!j.is_binary() || j.get_binary().size() != n * sizeof(T))
        throw Error("checkpoint: an array has the wrong size");
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), j.get_binary().data(), n * sizeof(T));
    return v;
}
template std::vector<double> from_binary(const nlohmann::json&, size_t);
template std::vector<float> from_binary(const nlohmann::json&, size_t);
template std::vector<int64_t> from_binary(const nlohmann::json&, size_t);
template std::vector<int32_t> from_binary(const nlohmann::json&, size_t);
template std::vector<uint32_t> from_binary(const nlohmann::json&, size_t);

Checkpoint::Checkpoint(std::string path, double every_seconds, const std::string& resume_path,
                       nlohmann::json fingerprint, Film& film, World& world)
    : m_path(std::move(path)),
      m_every(every_seconds),
      m_fingerprint(std::move(fingerprint)),
      m_film(film),
      m_world(world),
      m_pixel_units(size_t(film.width()) * size_t(film.height()), 0) {
    m_fingerprint["version"] = kCheckpointVersion;
    m_fingerprint["ranks"] = world.size();
    if (resume_path.empty()) return;
    const std::string file = rank_path(resume_path, world);
    std::ifstream in(file, std::ios::binary);
    if (!in) throw UsageError("--resume " + file + ": cannot read the file");
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    nlohmann::json j = nlohmann::json::from_cbor(bytes, true, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("fingerprint"))
        throw UsageError("--resume " + file + ": not a manylight checkpoint");
    // Another render's checkpoint: say what differs, the version first.
    const nlohmann::json& saved = j["fingerprint"];
    std::vector<std::string> keys{"version"};
    for (const auto& [key, value] : m_fingerprint.items())
        if (key != "version") keys.push_back(key);
    for (const auto& [key, value] : saved.items())
        if (!m_fingerprint.contains(key)) keys.push_back(key);
    for (const std::string& key : keys) {
        nlohmann::json here = m_fingerprint.value(key, nlohmann::json()),
                       there = saved.value(key, nlohmann::json());
        if (here != there)
            throw UsageError(fmt::format(
                "--resume {}: the checkpoint is of another render and cannot continue this one: "
                "{} is {} there, {} here",
                file, key, show(there), show(here)));
    }
    try {
        const size_t pixels = m_pixel_units.size();
        m_units = j.at("units").get<int64_t>();
        m_seconds = j.at("seconds").get<double>();
        m_pixel_units = from_binary<int64_t>(j.at("pixel_units"), pixels);
        m_film.set_sums(from_binary<double>(j.at("film"), pixels * 4),
                        j.at("nonfinite").get<uint64_t>());
        m_integrator_state = j.at("integrator");
    } catch (const nlohmann::json::exception& e) {
        throw UsageError("--resume " + file + ": a damaged checkpoint (" + e.what() + ")");
    } catch (const Error& e) {
        throw UsageError("--resume " + file + ": a damaged checkpoint (" + e.what() + ")");
    }
    m_resumed = true;
}

void Checkpoint::round_done(int64_t units, double elapsed) {
    if (m_path.empty()) return;
    const double since =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_last_save).count();
    if (m_world.root_decides(since >= m_every)) save(units, elapsed);
}

void Checkpoint::save(int64_t units, double elapsed) {
    if (m_path.empty()) return;
    nlohmann::json j = {{"fingerprint", m_fingerprint},
                        {"units", units},
                        {"seconds", elapsed},
                        {"pixel_units", to_binary(m_pixel_units)},
                        {"film", to_binary(m_film.sums())},
                        {"nonfinite", m_film.nonfinite_samples()},
                        {"integrator", m_state ? m_state() : nlohmann::json::object()}};
    std::vector<uint8_t> bytes = nlohmann::json::to_cbor(j);
    // Next to the target, then renamed: the checkpoint is whole or the last one stays.
    const std::filesystem::path target(rank_path(m_path, m_world));
    std::filesystem::path tmp = target;
    tmp += ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        out.close();
        if (!out) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            throw Error("cannot write checkpoint \"" + target.string() + "\"");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, target, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw Error("cannot write checkpoint \"" + target.string() + "\": rename failed");
    }
    m_last_save = std::chrono::steady_clock::now();
    ++m_saves;
}

}  // namespace ml
