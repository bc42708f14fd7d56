#include "view_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.h"

namespace ml {

namespace {

// A refinement starts once the view has rested this long: its preparation (VPLs, light trees)
// cannot be cancelled, and a moving view must get its next frame at once.
constexpr auto kRestBeforeRefining = std::chrono::milliseconds(250);
constexpr int kRefineGrowth = 4;  // each refining pass takes this many times the last's samples

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

nlohmann::json view_json(const std::array<float, 9>& v) {
    return {
        {"eye", {v[0], v[1], v[2]}}, {"target", {v[3], v[4], v[5]}}, {"up", {v[6], v[7], v[8]}}};
}

// The scene's viewpoint as eye, target and up; the target on the first surface the centre of
// the image sees (what orbiting turns about), else a tenth of the scene's size ahead.
std::array<float, 9> home_view(const Scene& scene) {
    Transform c = scene.desc().world_to_camera.inverse();
    Vec3 eye = c.point({0, 0, 0}), dir = normalize(c.vector({0, 0, 1})),
         up = normalize(c.vector({0, 1, 0}));
    float d = 0.1f * length(scene.bounds().diagonal());
    SurfaceInteraction si;
    if (scene.intersect(Ray{eye, dir, kInfinity, 0}, &si)) d = std::max(length(si.p - eye), 1e-3f);
    Vec3 t = eye + dir * d;
    return {eye.x, eye.y, eye.z, t.x, t.y, t.z, up.x, up.y, up.z};
}

float srgb_encode(float v) {
    v = std::clamp(v, 0.f, 1.f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}

}  // namespace

ViewRenderer::ViewRenderer(const Scene& scene, ViewConfig config)
    : m_scene(scene), m_config(std::move(config)), m_home(home_view(scene)), m_view(m_home) {
    m_settings.integrator = m_config.integrator;
    m_settings.spp = m_config.spp;
    m_settings.preview = m_config.preview;
}

ViewSettings ViewRenderer::settings() const {
    std::lock_guard lock(m_mutex);
    return m_settings;
}

void ViewRenderer::set_view(const std::array<float, 9>& v) {
    check_view(v);
    std::lock_guard lock(m_mutex);
    m_view = v;
    ++m_version;
    m_cancel = true;
    m_wake.notify_all();
}

void ViewRenderer::reset_view() { set_view(m_home); }

void ViewRenderer::set_settings(const nlohmann::json& j) {
    std::lock_guard lock(m_mutex);
    ViewSettings s = apply_view_settings(m_settings, j);
    bool only_exposure = s.vpls == m_settings.vpls && s.interleave == m_settings.interleave &&
                         s.filter == m_settings.filter && s.preview == m_settings.preview &&
                         s.integrator == m_settings.integrator && s.spp == m_settings.spp &&
                         s.refine_set == m_settings.refine_set;
    m_settings = s;
    if (only_exposure) {
        m_retonemap = true;
    } else {
        ++m_version;
        m_cancel = true;
    }
    m_wake.notify_all();
}

void ViewRenderer::request_save() {
    std::lock_guard lock(m_mutex);
    m_save = true;
    m_wake.notify_all();
}

void ViewRenderer::stop() {
    std::lock_guard lock(m_mutex);
    m_stop = true;
    m_cancel = true;
    m_wake.notify_all();
}

std::shared_ptr<const ViewMessage> ViewRenderer::hello() const {
    std::lock_guard lock(m_mutex);
    auto msg = std::make_shared<ViewMessage>();
    msg->text = nlohmann::json{{"type", "hello"},
                               {"scene", m_config.scene_path},
                               {"width", m_config.width},
                               {"height", m_config.height},
                               {"view", view_json(m_view)},
                               {"home", view_json(m_home)},
                               {"settings", m_settings.to_json()},
                               {"integrators", view_refine_integrators()}}
                    .dump();
    return msg;
}

std::shared_ptr<const ViewMessage> ViewRenderer::last_frame() const {
    std::lock_guard lock(m_mutex);
    return m_last_frame;
}

RenderOptions ViewRenderer::options_for(bool moving, const std::array<float, 9>& view,
                                        const ViewSettings& s, int spp) const {
    RenderOptions o;
    o.threads = m_config.threads;
    o.width = m_config.width;
    o.height = m_config.height;
    o.whole_image = true;
    o.look_at = view;
    o.spp = spp;
    if (moving) {
        o.integrator = "igi";
        o.set = {{"igi.vpls", std::to_string(s.vpls)},
                 {"igi.interleave", s.interleave},
                 {"igi.filter", std::to_string(s.filter)},
                 // One light sample of the sampled direct light per pixel (not four), and a
                 // BSDF sample with MIS only where the surface is glossy, blurred with the VPLs'
                 // light: the moving frames' budget goes to the VPLs (bench/RESULTS.md,
                 // "Issue 16, session 12").
                 {"lights.direct_samples", "1"},
                 {"lights.direct_mis", "glossy"},
                 {"igi.filter_direct", "true"}};
    } else {
        o.integrator = s.integrator;
        o.set = m_config.set;
        for (auto& [k, v] : parse_view_pairs(s.refine_set)) o.set[k] = v;
    }
    return o;
}

ViewRenderer::MovingFrame ViewRenderer::moving_frame(const std::array<float, 9>& view,
                                                     const ViewSettings& s, int divider,
                                                     const std::atomic<bool>* cancel) const {
    ML_ASSERT(divider >= 1, "a preview divider below 1");
    RenderOptions o = options_for(true, view, s, 1);
    o.cancel = cancel;
    const int w = m_config.width, h = m_config.height;
    o.width = (w + divider - 1) / divider;
    o.height = (h + divider - 1) / divider;
    RenderOutput out = render_built_scene(m_scene, o);
    if (divider == 1) return {std::move(out.image), std::move(out.figures)};
    MovingFrame frame{Image(w, h), std::move(out.figures)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) frame.image.at(x, y) = out.image.at(x / divider, y / divider);
    return frame;
}

std::string ViewRenderer::command_line(const std::array<float, 9>& v, const ViewSettings& s,
                                       const std::string& output) const {
    RenderOptions o = options_for(false, v, s, s.spp);
    std::string cmd =
        fmt::format("manylight render {} --integrator {} --spp {} --resolution {}x{}",
                    m_config.scene_path, o.integrator, s.spp, m_config.width, m_config.height);
    cmd += " --look-at";
    for (float x : v) cmd += fmt::format(" {:.9g}", x);
    for (const auto& [k, val] : o.set) cmd += fmt::format(" --set {}={}", k, val);
    return cmd + " -o " + output;
}

std::shared_ptr<const ViewMessage> ViewRenderer::frame_message(const Image& image,
                                                               nlohmann::json status,
                                                               float exposure) const {
    auto msg = std::make_shared<ViewMessage>();
    status["exposure"] = exposure;
    msg->text = status.dump();
    msg->frame = true;
    // Linear radiance to 8-bit sRGB through a table over [0, 1] after the exposure.
    static const std::vector<uint8_t> table = [] {
        std::vector<uint8_t> t(4097);
        for (int i = 0; i <= 4096; ++i)
            t[i] = uint8_t(std::lround(255.f * srgb_encode(i / 4096.f)));
        return t;
    }();
    const float scale = std::exp2(exposure) * 4096.f;
    msg->rgba.resize(image.pixels.size() * 4);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = image.pixels[i][c] * scale;
            msg->rgba[4 * i + c] = table[!(v > 0) ? 0 : v >= 4096.f ? 4096 : int(v)];
        }
        msg->rgba[4 * i + 3] = 255;
    }
    return msg;
}

void ViewRenderer::run(const std::function<void(std::shared_ptr<const ViewMessage>)>& broadcast) {
    uint64_t shown = 0;       // the version of the last moving frame
    bool full_shown = false;  // that frame was at full resolution
    int pass_spp = 0;         // samples of the last refining pass finished for `shown`
    bool converged = false;
    Image converged_image;
    std::array<float, 9> converged_view{};
    ViewSettings converged_settings;
    auto last_frame_end = std::chrono::steady_clock::now();
    auto error = [&](const std::string& what) {
        auto msg = std::make_shared<ViewMessage>();
        msg->text = nlohmann::json{{"type", "error"}, {"message", what}}.dump();
        std::fprintf(stderr, "manylight view: %s\n", what.c_str());
        broadcast(msg);
    };
    auto send_frame = [&](const Image& image, nlohmann::json status, float exposure) {
        auto msg = frame_message(image, status, exposure);
        {
            std::lock_guard lock(m_mutex);
            m_last_frame = msg;
            m_last_image = image;
            m_last_status = status;
        }
        broadcast(msg);
    };
    for (;;) {
        std::unique_lock lock(m_mutex);
        m_wake.wait(lock, [&] {
            return m_stop || m_version != shown || m_retonemap || m_save || !converged;
        });
        if (m_stop) return;
        const uint64_t version = m_version;
        const std::array<float, 9> view = m_view;
        const ViewSettings s = m_settings;
        bool retonemap = std::exchange(m_retonemap, false), save = std::exchange(m_save, false);
        m_cancel = false;
        if (retonemap && !m_last_image.pixels.empty()) {
            Image image = m_last_image;
            nlohmann::json status = m_last_status;
            lock.unlock();
            send_frame(image, status, s.exposure);
            continue;
        }
        if (save) {
            lock.unlock();
            if (!converged || converged_image.pixels.empty()) {
                error("the view has not converged yet: wait for the refinement to finish");
                continue;
            }
            std::string path = (std::filesystem::path(m_config.save_dir) /
                                fmt::format("view-{:03}.exr", ++m_saves))
                                   .string();
            try {
                write_image(path, converged_image);
                auto msg = std::make_shared<ViewMessage>();
                msg->text = nlohmann::json{{"type", "saved"},
                                           {"path", path},
                                           {"command",
                                            command_line(converged_view, converged_settings, path)}}
                                .dump();
                broadcast(msg);
            } catch (const std::exception& e) {
                error(e.what());
            }
            continue;
        }
        if (version == shown && full_shown) {
            // At rest: refine after a pause without changes.
            if (pass_spp == 0 &&
                m_wake.wait_for(lock, kRestBeforeRefining, [&] { return m_version != version; }))
                continue;
            lock.unlock();
            int spp = pass_spp == 0 ? 1 : std::min(pass_spp * kRefineGrowth, s.spp);
            RenderOptions o = options_for(false, view, s, spp);
            o.cancel = &m_cancel;
            auto t0 = std::chrono::steady_clock::now();
            try {
                RenderOutput out = render_built_scene(m_scene, o);
                if (m_cancel) continue;
                pass_spp = spp;
                converged = spp >= s.spp;
                double ms = 1000 * seconds_since(t0);
                nlohmann::json status = {{"type", "frame"},
                                         {"mode", converged ? "converged" : "refining"},
                                         {"integrator", s.integrator},
                                         {"spp", spp},
                                         {"target_spp", s.spp},
                                         {"progress", double(spp) / s.spp},
                                         {"frame_ms", ms},
                                         {"width", m_config.width},
                                         {"height", m_config.height},
                                         {"view", view_json(view)}};
                if (converged) {
                    converged_image = out.image;
                    converged_view = view;
                    converged_settings = s;
                    status["command"] = command_line(view, s, "view.exr");
                }
                send_frame(out.image, status, s.exposure);
            } catch (const std::exception& e) {
                // Wait for the next change rather than failing again at once.
                converged = true;
                converged_image = Image();
                error(std::string("refining: ") + e.what());
            }
            continue;
        }
        // Moving: an igi frame of the new view at 1/preview of the resolution (or the view
        // stopped after one: the same view at full resolution, which a move cancels).
        lock.unlock();
        const bool full = version == shown;
        const int divider = full ? 1 : s.preview;
        auto t0 = std::chrono::steady_clock::now();
        try {
            MovingFrame frame = moving_frame(view, s, divider, full ? &m_cancel : nullptr);
            if (full && m_cancel) continue;
            double ms = 1000 * seconds_since(t0);
            double interval = 1000 * seconds_since(last_frame_end);
            last_frame_end = std::chrono::steady_clock::now();
            shown = version;
            full_shown = divider == 1;
            pass_spp = 0;
            converged = false;
            send_frame(frame.image,
                       {{"type", "frame"},
                        {"mode", "moving"},
                        {"integrator", "igi"},
                        {"spp", 1},
                        {"target_spp", s.spp},
                        {"progress", 0.0},
                        {"frame_ms", ms},
                        {"interval_ms", interval},
                        {"vpls", frame.figures.vpls},
                        {"preview", divider},
                        {"width", m_config.width},
                        {"height", m_config.height},
                        {"view", view_json(view)}},
                       s.exposure);
        } catch (const std::exception& e) {
            shown = version;
            full_shown = true;
            converged = true;
            error(std::string("igi: ") + e.what());
        }
    }
}

}  // namespace ml
