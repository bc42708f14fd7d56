#include "media/nanovdb_medium.h"

#include <filesystem>

// NanoVDB reads files written with ZIP (zlib) or Blosc compression when told so.
#define NANOVDB_USE_ZIP
#define NANOVDB_USE_BLOSC
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/SampleFromVoxels.h>

namespace ml {

namespace {

using GridHandle = nanovdb::GridHandle<nanovdb::HostBuffer>;

class NanoVdbMedium final : public Medium {
public:
    NanoVdbMedium(const Transform& medium_to_world, GridHandle handle, const RGB& sigma_a,
                  const RGB& sigma_s, float g, float max_density, GridHandle temperature,
                  BlackbodyTable blackbody, float le_scale)
        : m_world_to_medium(medium_to_world.inverse()),
          m_handle(std::move(handle)),
          m_grid(m_handle.grid<float>()),
          m_temperature_handle(std::move(temperature)),
          m_temperature(m_temperature_handle ? m_temperature_handle.grid<float>() : nullptr),
          m_blackbody(std::move(blackbody)),
          m_le_scale(le_scale),
          m_sigma_a(sigma_a),
          m_sigma_s(sigma_s) {
        m_g = g;
        m_emits = m_temperature && !m_blackbody.empty() && le_scale > 0 && !sigma_a.is_black();
        auto box = m_grid->worldBBox();
        if (m_emits) {  // pbrt-v4: the union of both grids' bounds
            box.expand(m_temperature->worldBBox().min());
            box.expand(m_temperature->worldBBox().max());
        }
        m_p0 = Vec3(float(box.min()[0]), float(box.min()[1]), float(box.min()[2]));
        m_p1 = Vec3(float(box.max()[0]), float(box.max()[1]), float(box.max()[2]));
        // Trilinear interpolation stays within the voxels' values (the background is 0).
        const float sigma_t = (sigma_a + sigma_s).max_component();
        m_sigma_maj = max_density * sigma_t;
        // Cell by cell (as pbrt-v4's, up to 64^3): the largest voxel that interpolation mixes in
        // there.
        const auto ibox = m_grid->indexBBox();
        auto acc = m_grid->getAccessor();
        const auto dim = ibox.dim();
        m_majorants = MajorantGrid(
            majorant_res(std::max({dim[0], dim[1], dim[2]}), 64),
            [&](const Vec3& lo, const Vec3& hi) {
                nanovdb::Vec3f a(kInfinity), b(-kInfinity);
                for (int c = 0; c < 8; ++c) {
                    const Vec3 u((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y,
                                 (c & 4) ? hi.z : lo.z);
                    const Vec3 p(lerp(u.x, m_p0.x, m_p1.x), lerp(u.y, m_p0.y, m_p1.y),
                                 lerp(u.z, m_p0.z, m_p1.z));
                    const nanovdb::Vec3f i = m_grid->worldToIndexF(nanovdb::Vec3f(p.x, p.y, p.z));
                    for (int k = 0; k < 3; ++k)
                        a[k] = std::min(a[k], i[k]), b[k] = std::max(b[k], i[k]);
                }
                int i0[3], i1[3];
                for (int k = 0; k < 3; ++k) {
                    i0[k] = std::max(ibox.min()[k], int(std::floor(a[k])));
                    i1[k] = std::min(ibox.max()[k], int(std::floor(b[k])) + 1);
                }
                float most = 0;
                for (int z = i0[2]; z <= i1[2]; ++z)
                    for (int y = i0[1]; y <= i1[1]; ++y)
                        for (int x = i0[0]; x <= i1[0]; ++x)
                            most = std::max(most, acc.getValue(nanovdb::Coord(x, y, z)));
                return most * sigma_t;
            });
    }
    MediumProperties at(const Vec3& p_world) const override {
        const Vec3 p = m_world_to_medium.point(p_world);
        const float d = lookup(*m_grid, p);
        MediumProperties props{m_sigma_a * d, m_sigma_s * d, RGB()};
        if (m_emits) props.Le = m_blackbody.at(lookup(*m_temperature, p)) * m_le_scale;
        return props;
    }
    std::optional<MajorantSegment> majorant(const Ray& ray, float tmax) const override {
        return box_majorant(m_world_to_medium, m_p0, m_p1, m_sigma_maj, ray, tmax);
    }
    MajorantIterator majorants(const Ray& ray, float tmax) const override {
        return box_majorants(m_world_to_medium, m_p0, m_p1, m_majorants, m_sigma_maj, ray, tmax);
    }
    bool homogeneous() const override { return false; }
    std::string type() const override { return "nanovdb"; }

private:
    // The grid's value at medium-space point p, trilinear in index space.
    static float lookup(const nanovdb::FloatGrid& grid, const Vec3& p) {
        const nanovdb::Vec3f index = grid.worldToIndexF(nanovdb::Vec3f(p.x, p.y, p.z));
        using Sampler = nanovdb::SampleFromVoxels<nanovdb::FloatGrid::TreeType, 1, false>;
        return Sampler(grid.tree())(index);
    }
    Transform m_world_to_medium;
    GridHandle m_handle;
    const nanovdb::FloatGrid* m_grid;
    GridHandle m_temperature_handle;
    const nanovdb::FloatGrid* m_temperature;
    BlackbodyTable m_blackbody;
    float m_le_scale;
    RGB m_sigma_a, m_sigma_s;
    Vec3 m_p0, m_p1;  // the grid's bounds in medium space
    float m_sigma_maj = 0;
    MajorantGrid m_majorants;
};

GridHandle read_grid(const std::string& path, const std::string& name, const FileLoc& loc) {
    try {
        return nanovdb::io::readGrid<nanovdb::HostBuffer>(path, name);
    } catch (const std::exception& e) {
        throw_input_error(loc, "medium \"nanovdb\": cannot read \"{}\" from {}: {}", name, path,
                          e.what());
    }
}

}  // namespace

std::unique_ptr<Medium> create_nanovdb_medium(const ParameterList& params,
                                              const Transform& medium_to_world,
                                              const std::string& base_dir, const FileLoc& loc) {
    const std::string filename = params.get_string("filename", "");
    if (filename.empty()) throw_input_error(loc, "medium \"nanovdb\": no \"string filename\"");
    std::filesystem::path path(filename);
    if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
    const FileLoc& at = params.find("filename")->loc;
    if (!std::filesystem::is_regular_file(path))
        throw_input_error(at, "medium \"nanovdb\": no file {}", path.string());
    const std::string grid_name = params.get_string("gridname", "density");
    GridHandle density = read_grid(path.string(), grid_name, at);
    if (!density)
        throw_input_error(at, "medium \"nanovdb\": {} has no grid \"{}\"", path.string(),
                          grid_name);
    const nanovdb::FloatGrid* grid = density.grid<float>();
    if (!grid)
        throw_input_error(at, "medium \"nanovdb\": grid \"{}\" of {} does not hold floats",
                          grid_name, path.string());
    if (!grid->isFogVolume() && grid->gridClass() != nanovdb::GridClass::Unknown)
        throw_input_error(at, "medium \"nanovdb\": grid \"{}\" of {} is not a fog volume",
                          grid_name, path.string());
    float lo = 0, hi = 0;
    grid->tree().extrema(lo, hi);
    if (!(lo >= 0) || !std::isfinite(hi))
        throw_input_error(at,
                          "medium \"nanovdb\": grid \"{}\" of {} has negative or non-finite "
                          "densities",
                          grid_name, path.string());
    // pbrt-v4 makes a "temperature" grid glow as a blackbody, times "Lescale".
    const std::string temperature = params.get_string("temperaturename", "temperature");
    const float le_scale = params.get_float("Lescale", 1);
    const float offset =
                    params.get_float("temperatureoffset", params.get_float("temperaturecutoff", 0)),
                t_scale = params.get_float("temperaturescale", 1);
    if (!(le_scale >= 0) || !std::isfinite(le_scale))
        throw_input_error(loc, "medium \"nanovdb\": \"Lescale\" must be >= 0");
    GridHandle t_handle = read_grid(path.string(), temperature, at);
    BlackbodyTable blackbody;
    if (t_handle) {
        const nanovdb::FloatGrid* t = t_handle.grid<float>();
        if (!t)
            throw_input_error(at, "medium \"nanovdb\": grid \"{}\" of {} does not hold floats",
                              temperature, path.string());
        float t_lo = 0, t_hi = 0;
        t->tree().extrema(t_lo, t_hi);
        blackbody = BlackbodyTable(offset, t_scale, std::min(t_lo, 0.f), t_hi);
    }
    const float scale = params.get_float("scale", 1);
    const RGB sigma_a = params.get_rgb("sigma_a").value_or(RGB(1.f)) * scale,
              sigma_s = params.get_rgb("sigma_s").value_or(RGB(1.f)) * scale;
    for (const RGB& c : {sigma_a, sigma_s})
        if (!(c.r >= 0 && c.g >= 0 && c.b >= 0) || !c.is_finite())
            throw_input_error(loc,
                              "medium \"nanovdb\": \"sigma_a\", \"sigma_s\" and \"scale\" "
                              "must be finite and non-negative");
    const float g = params.get_float("g", 0);
    if (!(g > -1 && g < 1))
        throw_input_error(loc, "medium: \"g\" must be in (-1, 1) (it is {})", g);
    return std::make_unique<NanoVdbMedium>(medium_to_world, std::move(density), sigma_a, sigma_s, g,
                                           hi, std::move(t_handle), std::move(blackbody), le_scale);
}

}  // namespace ml
