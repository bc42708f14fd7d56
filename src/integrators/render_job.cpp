#include "integrators/render_job.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>

#include "camera/camera.h"
#include "core/parallel.h"
#include "core/stats.h"
#include "film/film.h"
#include "film/filter.h"
#include "film/image.h"
#include "integrators/registry.h"
#include "render/checkpoint.h"
#include "scene/default_scene.h"
#include "scene/scene.h"

namespace ml {

namespace {

// The realistic camera's "aperture" when it names an image file (pbrt-v4 reads any image; a
// colour image's R, G and B are averaged), relative to the scene's folder; empty otherwise.
ApertureImage aperture_file(const SceneDesc& desc) {
    const Param* a = desc.camera.params.find("aperture");
    if (desc.camera.name != "realistic" || !a) return {};
    const std::string name = desc.camera.params.get_string("aperture", "");
    if (name.empty() || ApertureImage::is_builtin_name(name)) return {};
    std::filesystem::path path(name);
    if (path.is_relative() && !desc.base_dir.empty())
        path = std::filesystem::path(desc.base_dir) / path;
    const Image image = read_image(path.lexically_normal().string(), a->loc);
    std::vector<float> values(image.pixels.size());
    double sum = 0;
    // pbrt-v4 decodes 8-bit files from sRGB.
    auto linear = [&](float v) { return image.low_dynamic_range ? srgb_to_linear(v) : v; };
    for (size_t i = 0; i < values.size(); ++i) {
        const RGB& p = image.pixels[i];
        values[i] = (linear(p.r) + linear(p.g) + linear(p.b)) / 3;
        sum += values[i];
    }
    if (!(sum > 0) || !std::isfinite(sum))
        throw_input_error(a->loc, "realistic camera: the aperture image \"{}\" passes no light",
                          name);
    return ApertureImage::from_values(image.width, image.height, std::move(values),
                                      image.low_dynamic_range && image.channels == 1);
}

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// pbrt-v4 sampler names to ours: the low-discrepancy ones all become Owen-scrambled Sobol'.
std::string sampler_for_pbrt_name(const std::string& name, const FileLoc& loc) {
    if (name.empty() || name == "sobol" || name == "zsobol" || name == "paddedsobol" ||
        name == "halton" || name == "pmj02bn")
        return "sobol";
    if (name == "independent" || name == "stratified") return name;
    throw_input_error(loc, "unknown sampler \"{}\"", name);
}

// The max depth an integrator renders with when nothing sets it (5 where it has none).
int default_max_depth(const IntegratorInfo& info) {
    for (const SettingDefault& d : integrator_settings(info))
        if (d.key == info.name + ".maxdepth") return std::stoi(d.value);
    return 5;
}

// The pixels of the image a render covers (pbrt-v4's film pixel bounds), [x0, x1) x [y0, y1).
struct PixelBounds {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The film's "cropwindow" (fractions of the image) or "pixelbounds" (pixels), as pbrt-v4 reads
// them: a crop window's corners are clamped to [0, 1] and rounded up to pixels (ceil(res * f) at
// both ends); pixel bounds are clamped to the image; with both, the crop window wins. Pixel
// bounds are pixels of the scene's resolution (`scene_w` x `scene_h`): under --resolution they
// keep their share of the image, rounded as a crop window is.
PixelBounds film_pixel_bounds(const ParameterList& film, int width, int height, int scene_w,
                              int scene_h, std::vector<std::string>& warnings) {
    PixelBounds pb{0, 0, width, height};
    // In single precision, as pbrt-v4 rounds (float(96) * 0.23f, not 96 * 0.23).
    auto from_fractions = [&](float fx0, float fx1, float fy0, float fy1) {
        auto at = [](int res, float f) {
            return int(std::ceil(float(res) * std::clamp(f, 0.f, 1.f)));
        };
        pb = {at(width, std::min(fx0, fx1)), at(height, std::min(fy0, fy1)),
              at(width, std::max(fx0, fx1)), at(height, std::max(fy0, fy1))};
    };
    const Param* crop = film.find("cropwindow");
    const Param* bounds = film.find("pixelbounds");
    if (bounds) {
        std::vector<int> b = film.get_ints("pixelbounds");
        if (b.size() != 4)
            throw_input_error(bounds->loc,
                              "film: \"pixelbounds\" needs 4 values (x0 x1 y0 y1), got {}",
                              b.size());
        // Corners in either order, as pbrt-v4's Bounds2i takes them.
        if (b[0] > b[1]) std::swap(b[0], b[1]);
        if (b[2] > b[3]) std::swap(b[2], b[3]);
        if (crop) {
            warnings.push_back(fmt::format(
                "{}: both \"pixelbounds\" and \"cropwindow\" are given; using the crop window "
                "(as pbrt-v4)",
                bounds->loc.to_string()));
        } else if (width != scene_w || height != scene_h) {
            // Rounded up, as a crop window's corners are, in integers (exact).
            auto scale = [](int v, int from, int to) {
                int64_t c = std::clamp<int64_t>(v, 0, from);
                return int((c * to + from - 1) / from);
            };
            pb = {scale(b[0], scene_w, width), scale(b[2], scene_h, height),
                  scale(b[1], scene_w, width), scale(b[3], scene_h, height)};
        } else {
            pb = {std::max(b[0], 0), std::max(b[2], 0), std::min(b[1], width),
                  std::min(b[3], height)};
            if (pb.x0 != b[0] || pb.y0 != b[2] || pb.x1 != b[1] || pb.y1 != b[3])
                warnings.push_back(fmt::format(
                    "{}: \"pixelbounds\" [{} {} {} {}] reach past the {}x{} image; clamped",
                    bounds->loc.to_string(), b[0], b[1], b[2], b[3], width, height));
        }
    }
    if (crop) {
        std::vector<float> c = film.get_floats("cropwindow");
        if (c.size() != 4)
            throw_input_error(
                crop->loc, "film: \"cropwindow\" needs 4 values (x0 x1 y0 y1), got {}", c.size());
        for (float v : c)
            if (!std::isfinite(v))
                throw_input_error(crop->loc, "film: \"cropwindow\" values must be finite");
        from_fractions(c[0], c[1], c[2], c[3]);
    }
    if (pb.x1 <= pb.x0 || pb.y1 <= pb.y0)
        throw_input_error((crop ? crop : bounds)->loc,
                          "film: the {} leaves no pixel of the {}x{} image (pixel bounds [{} {} "
                          "{} {}])",
                          crop ? "crop window" : "pixel bounds", width, height, pb.x0, pb.x1, pb.y0,
                          pb.y1);
    return pb;
}

// Everything render_scene makes from the description and the options before the scene is built:
// made first, so that bad settings are reported before the (long) build.
struct RenderPlan {
    int width = 0, height = 0, spp = 0;   // the film that is rendered: the crop's size
    int full_width = 0, full_height = 0;  // the image's
    PixelBounds crop;
    float max_component = kInfinity, imaging_ratio = 1;
    std::string name, sampler_name;
    uint64_t seed = 0;
    int max_depth = 5;  // the integrator's "maxdepth", for the bias check's path tracer
    std::unique_ptr<Filter> filter;
    std::optional<PerspectiveCamera> camera;
    std::unique_ptr<Integrator> integrator;
    std::unique_ptr<Sampler> sampler;
    std::vector<std::string> warnings;
    std::string output_hint;
    nlohmann::json fingerprint;  // what a checkpoint of this render must match
};

// The camera-to-world transform of RenderOptions::look_at: the scene's handedness (a
// `Scale -1 1 1` before its LookAt) is kept.
Transform look_at_camera(const std::array<float, 9>& v, const Transform& scene_world_to_camera) {
    bool ok = false;
    Transform world_to_camera =
        Transform::look_at({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, &ok);
    if (!ok)
        throw UsageError(
            "--look-at: the eye and the target must differ, and up must not be along the view");
    if (scene_world_to_camera.swaps_handedness())
        world_to_camera = Transform::scale({-1, 1, 1}) * world_to_camera;
    return world_to_camera.inverse();
}

RenderPlan make_plan(const SceneDesc& desc, const RenderOptions& opt) {
    RenderPlan plan;

    // Film: resolution from the scene unless overridden; a size that cannot fit is an error.
    const ParameterList& film_params = desc.film.params;
    if (!desc.film.name.empty() && desc.film.name != "rgb" && desc.film.name != "gbuffer")
        throw_input_error(desc.film.loc, "unknown film \"{}\"", desc.film.name);
    const int scene_width = film_params.get_int("xresolution", 1280);
    const int scene_height = film_params.get_int("yresolution", 720);
    int width = scene_width, height = scene_height;
    if (opt.width) width = *opt.width;
    if (opt.height) height = *opt.height;
    if (width <= 0 || height <= 0)
        throw_input_error(desc.film.loc, "resolution {}x{} must be positive", width, height);
    if (int64_t(width) * height > (int64_t(1) << 27) || width > 65536 || height > 65536)
        throw_input_error(desc.film.loc,
                          "resolution {}x{} is too large (at most 2^27 pixels, 65536 a side)",
                          width, height);
    PixelBounds crop =
        film_pixel_bounds(film_params, width, height, scene_width, scene_height, plan.warnings);
    if (opt.whole_image) crop = {0, 0, width, height};
    plan.output_hint = film_params.get_string("filename", "");
    float max_component = film_params.get_float("maxcomponentvalue", kInfinity);
    film_params.get_bool("savefp16", true);
    const float film_diagonal = film_params.get_float("diagonal", 35.f);
    // pbrt-v4's RGB film scales what its sensor sees by the exposure time, the camera's shutter
    // interval (shutterclose - shutteropen, 1 by default), times iso / 100. Its default sensor,
    // cie1931, with no white balance, is the identity on RGB; the spectral sensors and white
    // balancing need spectra, which manylight does not carry, so they are errors. A shutter that
    // opens and closes at one instant, which pbrt-v4 refuses, freezes time there: it is taken as
    // an exposure of 1 (a closing before the opening is the camera's error).
    float exposure = desc.camera.params.get_float("shutterclose", 1.f) -
                     desc.camera.params.get_float("shutteropen", 0.f);
    if (!(exposure > 0)) exposure = 1.f;
    const float iso = film_params.get_float("iso", 100.f);
    if (!(iso > 0) || !std::isfinite(iso))
        throw_input_error(film_params.find("iso")->loc,
                          "\"iso\" must be positive and finite, got {}", iso);
    const float imaging_ratio = exposure * iso / 100.f;
    if (std::string sensor = film_params.get_string("sensor", "cie1931"); sensor != "cie1931")
        throw_input_error(film_params.find("sensor")->loc,
                          "sensor \"{}\" needs spectral rendering; manylight renders in RGB and "
                          "supports only \"cie1931\"",
                          sensor);
    if (float wb = film_params.get_float("whitebalance", 0.f); wb != 0)
        throw_input_error(film_params.find("whitebalance")->loc,
                          "whitebalance {} needs spectral rendering; manylight renders in RGB and "
                          "supports only 0 (none)",
                          wb);
    film_params.check_unused();

    // Sampler.
    const ParameterList& sp = desc.sampler.params;
    std::string sampler_name = opt.sampler.empty()
                                   ? sampler_for_pbrt_name(desc.sampler.name, desc.sampler.loc)
                                   : opt.sampler;
    int spp = sp.get_int("pixelsamples", 16);
    if (sampler_name == "stratified" && (sp.has("xsamples") || sp.has("ysamples")))
        spp = sp.get_int("xsamples", 4) * sp.get_int("ysamples", 4);
    sp.get_bool("jitter", true);
    sp.get_string("randomization", "");
    uint64_t seed = uint64_t(sp.get_int("seed", 0));
    sp.check_unused();
    if (opt.spp) spp = *opt.spp;
    if (opt.seed) seed = *opt.seed;
    if (opt.time_limit > 0 && !opt.spp) spp = 1 << 24;  // the time decides
    if (spp <= 0) throw UsageError("samples per pixel must be positive");

    // Filter and camera.
    std::string filter_name = desc.filter.name.empty() ? "gaussian" : desc.filter.name;
    auto filter = create_filter(filter_name, desc.filter.params, desc.filter.loc);
    desc.filter.params.check_unused();
    // --look-at places a still camera; otherwise the scene's, moving if it does.
    AnimatedTransform camera_to_world =
        opt.look_at ? AnimatedTransform(look_at_camera(*opt.look_at, desc.world_to_camera))
                    : desc.camera_to_world();
    plan.camera.emplace(desc.camera.params, camera_to_world, width, height,
                        desc.camera.name.empty() ? "perspective" : desc.camera.name, film_diagonal,
                        desc.base_dir, aperture_file(desc));
    desc.camera.params.check_unused();
    plan.camera->set_crop(crop.x0, crop.y0, crop.x1 - crop.x0, crop.y1 - crop.y0);

    // Integrator: the command line's, else the scene's where we have it, else path.
    std::string scene_integrator = integrator_for_pbrt_name(desc.integrator.name);
    std::string name = opt.integrator;
    if (name.empty()) name = scene_integrator.empty() ? "path" : scene_integrator;
    name = resolve_integrator_alias(name);
    if (opt.integrator.empty() && !desc.integrator.name.empty() && scene_integrator.empty())
        plan.warnings.push_back(fmt::format(
            "{}: the scene asks for integrator \"{}\", which manylight does not have; rendering "
            "with \"path\" (its parameters but maxdepth are ignored)",
            desc.integrator.loc.to_string(), desc.integrator.name));
    const IntegratorInfo* info = find_integrator(name);
    if (!info) throw UsageError("unknown integrator \"" + name + "\"");
    if (info->needs_camera_importance && !plan.camera->has_importance())
        throw_input_error(desc.camera.loc,
                          "integrator \"{}\" carries light paths to the camera, which needs the "
                          "camera's importance; the {} camera has none (as in pbrt-v4): render "
                          "it with path or a many-light integrator",
                          name, desc.camera.name);
    if (info->splats_past_film_edge) {
        const Vec2 r = filter->radius();
        plan.camera->set_raster_margin(Vec2(std::max(0.f, r.x - 0.5f), std::max(0.f, r.y - 0.5f)));
    }
    std::map<std::string, std::string> overrides = opt.set;
    // The scene's parameters apply only to the integrator they were written for, except
    // "maxdepth": it is the scene's light transport (the longest path), and means the same in
    // every pbrt-v4 integrator and ours, so a scene written for `path` keeps its depth under
    // `mdlightcuts`. --max-depth and --set NAME.maxdepth override it.
    const ParameterList* scene_params =
        name == scene_integrator ? &desc.integrator.params : nullptr;
    if (opt.max_depth)
        overrides[name + ".maxdepth"] = std::to_string(*opt.max_depth);
    else if (!scene_params && desc.integrator.params.has("maxdepth") &&
             !overrides.count(name + ".maxdepth"))
        overrides[name + ".maxdepth"] =
            std::to_string(desc.integrator.params.get_int("maxdepth", 5));
    // pbrt-v4's "mlt" takes its samples per pixel from "mutationsperpixel" (100 unless given),
    // not from the sampler; --spp and --time-limit still decide.
    if (scene_params && desc.integrator.name == "mlt") {
        const int mutations = desc.integrator.params.get_int("mutationsperpixel", 100);
        if (mutations <= 0)
            throw_input_error(desc.integrator.loc, "\"mutationsperpixel\" must be positive");
        if (!opt.spp && !(opt.time_limit > 0)) spp = mutations;
    }
    Settings settings(name, scene_params, overrides);
    auto integrator = info->create(settings);
    settings.check_unused();
    validate(opt.bias_check);
    // Participating media: every integrator but `whitted`, `direct` and `cmlt` (whose packets
    // of lens perturbations trace no media) carries light through them.
    if (has_media(desc)) {
        static const std::set<std::string> kMedia = {
            "path",        "lighttracer", "bdpt",
            "pssmlt",      "mlt",         "vpl",
            "lightcuts",   "mdlightcuts", "stochasticlightcuts",
            "bdlightcuts", "igi"};
        if (!kMedia.count(name))
            throw UsageError(fmt::format(
                "integrator \"{}\" does not render participating media (the scene has "
                "MakeNamedMedium/MediumInterface); render it with --integrator path, bdpt, "
                "lighttracer, pssmlt, mlt, vpl, lightcuts, mdlightcuts, stochasticlightcuts, "
                "bdlightcuts or igi",
                name));
        // Light emitted by a medium reaches the film only by eye paths (no light path starts
        // in one): `path`'s, BDPT's strategy s = 0 (so `pssmlt` too), bdlightcuts' eye paths
        // with their remainders, and the other many-light integrators' camera paths with paths
        // continued past their gather points for it (manylight/gather.h).
        static const std::set<std::string> kEmission = {
            "path",        "bdpt",      "pssmlt",
            "vpl",         "lightcuts", "mdlightcuts",
            "bdlightcuts", "igi",       "stochasticlightcuts"};
        if (!kEmission.count(name))
            for (const auto& m : desc.media)
                if (m->emits())
                    throw UsageError(fmt::format(
                        "integrator \"{}\" does not carry light emitted by a medium (no light "
                        "path starts in one, and Veach's paths end on lights); render it with "
                        "--integrator path, bdpt, pssmlt or "
                        "one of the many-light integrators",
                        name));
    }
    if (bias_check_enabled(opt.bias_check, name))
        plan.max_depth =
            settings.has("maxdepth") ? settings.get_int("maxdepth", 5) : default_max_depth(*info);

    if (!opt.checkpoint.empty() || !opt.resume.empty()) {
        if (!integrator->can_checkpoint()) {
            std::vector<std::string> can;
            for (const IntegratorInfo& other : integrator_registry())
                if (other.create(Settings(other.name, nullptr, {}))->can_checkpoint())
                    can.push_back(other.name);
            throw UsageError(fmt::format(
                "--checkpoint/--resume: integrator \"{}\" with these settings cannot save its "
                "state; these can: {}",
                name, fmt::join(can, ", ")));
        }
        if (!(opt.checkpoint_every >= 0))
            throw UsageError("--checkpoint-every: expected seconds >= 0");
        nlohmann::json look_at = opt.look_at ? nlohmann::json(*opt.look_at) : nlohmann::json();
        plan.fingerprint = {
            {"scene", opt.scene_id},         {"integrator", name}, {"settings", overrides},
            {"resolution", {width, height}}, {"seed", seed},       {"spp", spp},
            {"sampler", sampler_name},       {"look_at", look_at}};
        if (crop.x0 != 0 || crop.y0 != 0 || crop.x1 != width || crop.y1 != height)
            plan.fingerprint["crop"] = {crop.x0, crop.x1, crop.y0, crop.y1};
    }
    plan.sampler = create_sampler(sampler_name, spp, seed);
    plan.full_width = width;
    plan.full_height = height;
    plan.crop = crop;
    plan.width = crop.x1 - crop.x0;
    plan.height = crop.y1 - crop.y0;
    plan.spp = spp;
    plan.max_component = max_component;
    plan.imaging_ratio = imaging_ratio;
    plan.name = name;
    plan.sampler_name = sampler_name;
    plan.seed = seed;
    plan.filter = std::move(filter);
    plan.integrator = std::move(integrator);
    return plan;
}

// Across ranks: rank 0 gathers the ranks' render times and sums their films and images (each
// holds its own share; see RenderContext::world).
void reduce_to_root(World& world, Film& film, RenderResult& result, RenderFigures& fig,
                    double seconds_render) {
    // A test of the abort path (tests/test_mpi.cpp): this rank fails while the others wait in
    // the reduction below; the run must end with the message, not hang.
    if (const char* fail = std::getenv("MANYLIGHT_TEST_FAIL_RANK");
        fail && std::atoi(fail) == world.rank())
        throw InternalError(
            fmt::format("rank {} fails on purpose (MANYLIGHT_TEST_FAIL_RANK)", world.rank()));
    fig.seconds_render_per_rank = world.gather(seconds_render);
    auto t = std::chrono::steady_clock::now();
    film.reduce_to_root(world);
    // Extra images hold zeros where a rank did not render: summed as the film is. Every rank
    // made the same images (the same integrator), so the collectives pair up.
    for (auto* images : {&result.aovs, &result.debug_images}) {
        if (world.all_min(int64_t(images->size())) !=
            world.all_sum(int64_t(images->size())) / world.size())
            throw InternalError("the ranks made different extra images");
        for (auto& [image_name, image] : *images) {
            std::vector<float> v(image.pixels.size() * 3);
            for (size_t i = 0; i < image.pixels.size(); ++i)
                for (int c = 0; c < 3; ++c) v[i * 3 + size_t(c)] = image.pixels[i][c];
            world.reduce_sum(v.data(), v.size());
            for (size_t i = 0; i < image.pixels.size(); ++i)
                image.pixels[i] = RGB(v[i * 3], v[i * 3 + 1], v[i * 3 + 2]);
        }
    }
    fig.seconds_reduce = seconds_since(t);
}

// Renders the plan on the built scene.
RenderOutput run_plan(RenderPlan& plan, const Scene& scene, const RenderOptions& opt,
                      RenderOutput out) {
    RenderFigures& fig = out.figures;
    const int width = plan.width, height = plan.height,
              threads = opt.threads > 0 ? opt.threads : default_thread_count();
    const std::string& name = plan.name;
    ThreadLimit limit(threads);
    World& world = opt.world ? *opt.world : local_world();
    const bool distributed = world.size() > 1;
    Film film(width, height, plan.max_component, plan.imaging_ratio);
    Progress progress(fmt::format("{} {}x{}", name, width, height), opt.progress && world.root(),
                      opt.on_progress);
    // Across ranks the render (and its time limit) starts when every rank has built the scene.
    if (distributed) world.barrier();
    // Under a time limit the bias check takes its share of it, after the render.
    const bool check = bias_check_enabled(opt.bias_check, name);
    const double time_limit =
        check && opt.time_limit > 0 ? opt.time_limit * (1 - opt.bias_check.share) : opt.time_limit;
    RenderContext ctx{scene,    *plan.camera, *plan.filter, film,     *plan.sampler,
                      plan.spp, time_limit,   &progress,    plan.seed};
    ctx.cancel = opt.cancel;
    if (distributed) ctx.world = &world;
    // A checkpoint to save to or resume from: a resumed render's film starts with the saved
    // sums, and its time limit counts the time already spent.
    std::optional<Checkpoint> checkpoint;
    if (!opt.checkpoint.empty() || !opt.resume.empty()) {
        checkpoint.emplace(opt.checkpoint, opt.checkpoint_every, opt.resume, plan.fingerprint, film,
                           world);
        ctx.checkpoint = &*checkpoint;
        if (checkpoint->resuming()) {
            fig.resumed_from = checkpoint->units();
            ctx.start -= std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                std::chrono::duration<double>(checkpoint->seconds()));
        }
    }
    RenderResult result;
    stats::reset();
    auto t_render = std::chrono::steady_clock::now();
    result = plan.integrator->render(ctx);
    if (checkpoint) fig.checkpoint_saves = checkpoint->saves();
    if (distributed) reduce_to_root(world, film, result, fig, seconds_since(t_render));
    fig.seconds_render = seconds_since(t_render);
    progress.done();
    stats::RayCounts rays = stats::total();
    if (distributed) {
        rays.camera = uint64_t(world.all_sum(int64_t(rays.camera)));
        rays.closest = uint64_t(world.all_sum(int64_t(rays.closest)));
        rays.shadow = uint64_t(world.all_sum(int64_t(rays.shadow)));
        rays.nonfinite_splats = uint64_t(world.all_sum(int64_t(rays.nonfinite_splats)));
        fig.ranks = world.size();
        fig.bytes_reduced = world.bytes_reduced();
        fig.bytes_broadcast = world.bytes_broadcast();
    }

    out.image = film.to_image();
    // A crop is written as the data window of the whole image (as pbrt-v4 writes it).
    if (plan.width != plan.full_width || plan.height != plan.full_height) {
        auto place = [&](Image& image) {
            image.x = plan.crop.x0, image.y = plan.crop.y0;
            image.full_width = plan.full_width, image.full_height = plan.full_height;
        };
        place(out.image);
        for (auto* images : {&result.aovs, &result.debug_images})
            for (auto& [image_name, image] : *images)
                if (image.width == plan.width && image.height == plan.height) place(image);
    }
    fig.nonfinite_samples = film.nonfinite_samples() + rays.nonfinite_splats;
    if (fig.nonfinite_samples > 0)
        fig.warnings.push_back(fmt::format(
            "{} samples had a NaN or infinite channel and were dropped (film.nonfinite_samples)",
            fig.nonfinite_samples));
    // Splat-only integrators (lighttracer) add no camera samples: only pixel integrators count.
    if (opt.time_limit > 0 && result.spp == 0 && film.pixels_without_samples() > 0 &&
        film.pixels_without_samples() < size_t(width) * height) {
        fig.pixels_without_samples = film.pixels_without_samples();
        fig.warnings.push_back(fmt::format(
            "the time limit ended the first pass: {} of {} pixels have no sample; raise "
            "--time-limit",
            fig.pixels_without_samples, size_t(width) * height));
    }
    fig.integrator = name;
    fig.sampler = plan.sampler_name;
    fig.spp = result.spp;
    fig.width = width;
    fig.height = height;
    fig.threads = threads;
    fig.rays_camera = rays.camera;
    fig.rays_closest = rays.closest;
    fig.rays_shadow = rays.shadow;
    fig.triangles = scene.triangle_count();
    fig.lights = scene.lights().size();
    for (const auto& l : scene.lights())
        if (l->type() == LightType::DeltaPosition) ++fig.point_lights;
    // Many-light integrators report the point-light set they shaded with instead.
    if (result.point_lights > 0) fig.point_lights = result.point_lights;
    fig.vpls = result.vpls;
    fig.integrator_stats = std::move(result.stats);
    fig.warnings.insert(fig.warnings.end(), result.warnings.begin(), result.warnings.end());
    out.aovs = std::move(result.aovs);
    out.debug_images = std::move(result.debug_images);

    // The bias check, on rank 0 (which holds the image), after the figures above: its rays are
    // not the render's. The time limit counts from the render's start, as a total.
    if (check && world.root()) {
        BiasCheckInput in{
            scene,
            *plan.camera,
            *plan.filter,
            out.image,
            plan.max_component,
            plan.imaging_ratio,
            plan.seed,
            plan.max_depth,
            bias_check_spp(opt.bias_check, result.spp > 0 ? result.spp : plan.spp, width, height),
            opt.time_limit,
            ctx.start,
            opt.cancel};
        fig.bias_check = run_bias_check(in, opt.bias_check);
        if (std::string w = fig.bias_check->warning(); !w.empty()) fig.warnings.push_back(w);
    }
    return out;
}

}  // namespace

RenderOutput render_scene(SceneDesc desc, const RenderOptions& opt) {
    RenderPlan plan = make_plan(desc, opt);
    RenderOutput out;
    out.figures.warnings = std::move(plan.warnings);
    out.figures.output_hint = plan.output_hint;
    int threads = opt.threads > 0 ? opt.threads : default_thread_count();
    double build = 0;
    std::unique_ptr<Scene> scene;
    {
        ThreadLimit limit(threads);
        auto t_build = std::chrono::steady_clock::now();
        scene = std::make_unique<Scene>(std::move(desc));
        scene->set_shutter(plan.camera->shutter_open(), plan.camera->shutter_close());
        build = seconds_since(t_build);
    }
    out.figures.seconds_build = build;
    return run_plan(plan, *scene, opt, std::move(out));
}

LoadedScene load_scene(const std::string& path) {
    auto t0 = std::chrono::steady_clock::now();
    LoadedScene loaded{path.empty() ? parse_scene_string(default_scene_text(), ".", "<cornell-box>")
                                    : parse_scene_file(path),
                       0, ""};
    loaded.seconds_load = seconds_since(t0);
    // The scene's identity for checkpoints: its file's text (what it includes is not hashed).
    std::string text = default_scene_text();
    if (!path.empty()) {
        std::ifstream in(path, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    loaded.id = fmt::format("{:016x}", fingerprint_hash(text));
    return loaded;
}

RenderOutput render_loaded_scene(LoadedScene scene, const RenderOptions& options) {
    RenderOptions o = options;
    if (o.scene_id.empty()) o.scene_id = scene.id;
    RenderOutput out = render_scene(std::move(scene.desc), o);
    out.figures.seconds_load = scene.seconds_load;
    struct rusage usage {};
    if (getrusage(RUSAGE_SELF, &usage) == 0) out.figures.peak_rss_mb = usage.ru_maxrss / 1024.0;
    return out;
}

RenderOutput render_built_scene(const Scene& scene, const RenderOptions& opt) {
    RenderPlan plan = make_plan(scene.desc(), opt);
    RenderOutput out;
    out.figures.warnings = std::move(plan.warnings);
    out.figures.output_hint = plan.output_hint;
    return run_plan(plan, scene, opt, std::move(out));
}

nlohmann::json RenderFigures::to_json() const {
    uint64_t total = rays_closest + rays_shadow;
    nlohmann::json j = {
        {"integrator", integrator},
        {"sampler", sampler},
        {"spp", spp},
        {"resolution", {width, height}},
        {"threads", threads},
        {"seconds",
         {{"load", seconds_load},
          {"build", seconds_build},
          {"render", seconds_render},
          {"total", seconds_load + seconds_build + seconds_render +
                        (bias_check ? bias_check->seconds : 0.0)}}},
        {"rays",
         {{"camera", rays_camera},
          {"closest", rays_closest},
          {"shadow", rays_shadow},
          {"total", total}}},
        {"rays_per_second", seconds_render > 0 ? double(total) / seconds_render : 0.0},
        {"scene", {{"triangles", triangles}}},
        {"lights", {{"total", lights}, {"point_lights", point_lights}, {"vpls", vpls}}},
        {"memory", {{"peak_rss_mb", peak_rss_mb}}},
        {"film",
         {{"nonfinite_samples", nonfinite_samples},
          {"pixels_without_samples", pixels_without_samples}}}};
    if (ranks > 1)
        j["mpi"] = {{"ranks", ranks},
                    {"seconds_render_per_rank", seconds_render_per_rank},
                    {"seconds_reduce", seconds_reduce},
                    {"bytes_reduced_per_rank", bytes_reduced},
                    {"bytes_broadcast", bytes_broadcast}};
    if (bias_check) j["bias_check"] = bias_check->to_json();
    if (checkpoint_saves > 0 || resumed_from >= 0)
        j["checkpoint"] = {{"saves", checkpoint_saves}, {"resumed_from", resumed_from}};
    for (const auto& [key, value] : integrator_stats.items()) j[key] = value;
    return j;
}

}  // namespace ml
