// The two estimators a pssmlt chain can explore: BDPT's paths of one depth (the default) and the
// path tracer.
#include <algorithm>
#include <cmath>

#include "bidir/bdpt_estimator.h"
#include "core/stats.h"
#include "integrators/path/path.h"
#include "integrators/pssmlt/estimator.h"
#include "render/settings.h"

namespace ml {

namespace {

class BdptPrimaryEstimator final : public PrimaryEstimator {
public:
    BdptPrimaryEstimator(const Scene& scene, const PerspectiveCamera& camera, int max_depth)
        : m_bdpt(scene, camera), m_max_depth(max_depth) {}
    int depth_count() const override { return m_max_depth + 1; }
    int stream_count() const override { return kBdptStreamCount; }
    PrimaryPathSample sample(MltSampler& sampler, int depth,
                             ScratchBuffer& scratch) const override {
        BdptPathSample s = m_bdpt.sample_depth(
            sampler, depth, scratch, [&](BdptStream stream) { sampler.start_stream(int(stream)); });
        return {s.L, s.p_raster};
    }

private:
    BdptEstimator m_bdpt;
    int m_max_depth;
};

class PathPrimaryEstimator final : public PrimaryEstimator {
public:
    PathPrimaryEstimator(const Scene& scene, const PerspectiveCamera& camera, int max_depth)
        : m_scene(scene),
          m_camera(camera),
          m_path(Settings("path", nullptr, {{"path.maxdepth", std::to_string(max_depth)}})) {
        m_path.prepare(scene);
    }
    int depth_count() const override { return 1; }
    int stream_count() const override { return 1; }
    PrimaryPathSample sample(MltSampler& sampler, int depth,
                             ScratchBuffer& scratch) const override {
        sampler.start_stream(0);
        Vec2 u = sampler.get_pixel_2d();
        CameraSample cs;
        cs.p_film = m_camera.raster_point(u);
        cs.time = sampler.get_1d();
        cs.p_lens = sampler.get_2d();
        Ray ray = m_camera.generate_ray(cs);
        stats::count_camera_ray();
        Point2i pixel{std::clamp(int(std::floor(cs.p_film.x)), 0, m_camera.width() - 1),
                      std::clamp(int(std::floor(cs.p_film.y)), 0, m_camera.height() - 1)};
        return {m_path.li(ray, m_scene, sampler, scratch, pixel) * m_camera.raster_area_ratio(),
                cs.p_film};
    }

private:
    const Scene& m_scene;
    const PerspectiveCamera& m_camera;
    PathIntegrator m_path;
};

}  // namespace

std::unique_ptr<PrimaryEstimator> make_primary_estimator(const std::string& name,
                                                         const Scene& scene,
                                                         const PerspectiveCamera& camera,
                                                         int max_depth) {
    if (name == "bdpt") return std::make_unique<BdptPrimaryEstimator>(scene, camera, max_depth);
    if (name == "path") return std::make_unique<PathPrimaryEstimator>(scene, camera, max_depth);
    throw UsageError("pssmlt: estimator must be bdpt or path, not \"" + name + "\"");
}

}  // namespace ml
