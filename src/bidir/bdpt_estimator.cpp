#include "bidir/bdpt_estimator.h"

#include <vector>

#include "bidir/connect.h"
#include "bidir/subpaths.h"
#include "lights/light_sampler.h"

namespace ml {

BdptEstimator::BdptEstimator(const Scene& scene, const PerspectiveCamera& camera,
                             const std::string& light_sampler)
    : m_scene(scene),
      m_camera(camera),
      m_light_sampler(std::make_unique<LightSampler>(light_sampler, scene.lights())) {}

BdptEstimator::~BdptEstimator() = default;

BdptPathSample BdptEstimator::sample_depth(
    Sampler& sampler, int depth, ScratchBuffer& scratch,
    const std::function<void(BdptStream)>& start_stream) const {
    BdptPathSample out;
    const bool emitting_media = m_scene.has_emitting_media();
    if ((m_scene.lights().empty() && !emitting_media) || depth < 0) return out;
    auto stream = [&](BdptStream s) {
        if (start_stream) start_stream(s);
    };
    BdptScene ctx(m_scene, m_camera, *m_light_sampler);

    // The strategy, uniformly among the depth + 2 that make paths of this depth.
    stream(BdptStream::Camera);
    int s = 0, t = 2, n_strategies = 1;
    if (depth > 0) {
        n_strategies = depth + 2;
        s = std::min(int(sampler.get_1d() * float(n_strategies)), n_strategies - 1);
        t = n_strategies - s;
    }

    // The camera subpath, exactly t vertices.
    Vec2 u_film = sampler.get_pixel_2d();
    CameraSample cs;
    cs.p_film = m_camera.raster_point(u_film);
    cs.time = sampler.get_1d();
    cs.p_lens = sampler.get_2d();
    out.p_raster = cs.p_film;
    Ray ray = m_camera.generate_ray(cs);
    thread_local std::vector<PathVertex> camera_vertices, light_vertices;
    thread_local std::vector<RGB> medium_emission;
    camera_vertices.resize(size_t(t));
    light_vertices.resize(size_t(std::max(s, 1)));
    medium_emission.resize(size_t(t));
    // Strategy s = 0 also takes the light that media emit after depth - 1 scattering vertices
    // (subpaths.h: a path of this depth that only it makes), whether or not the camera subpath
    // goes on to its t-th vertex.
    const bool media_emission = emitting_media && s == 0 && depth >= 1;
    const int nc = generate_camera_subpath(ctx, ray, sampler, scratch, t, camera_vertices.data(),
                                           media_emission ? medium_emission.data() : nullptr);
    // A camera ray's value counts the area it was drawn over (the film and its margin) against
    // the film's.
    const float scale = float(n_strategies) * m_camera.raster_area_ratio();
    if (media_emission) out.L = medium_emission[size_t(depth - 1)] * scale;
    if (nc != t) return out;

    // The light subpath, exactly s vertices.
    stream(BdptStream::Light);
    if (generate_light_subpath(ctx, sampler, scratch, s, ray.time, light_vertices.data()) != s)
        return out;

    // The connection. A splat's value is already per camera sample (and s = 0 never splats).
    stream(BdptStream::Connection);
    Connection c = connect_bdpt(ctx, light_vertices.data(), camera_vertices.data(), s, t, sampler);
    if (c.splat) out.p_raster = c.p_raster;
    out.L += c.L * (c.splat ? float(n_strategies) : scale);
    return out;
}

}  // namespace ml
