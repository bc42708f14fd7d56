// The viewer's render thread (`manylight view`): one scene built once, a view (eye, target, up)
// and settings that clients change, and frames for them. While the view changes it renders
// `igi` frames (one sample per pixel), at 1/preview of the resolution while it moves (what
// viewports do: the first frame after a move must come fast) and once at full resolution when
// it stops; once it rests it refines with the chosen integrator
// (path, lightcuts, mdlightcuts) in passes of 1, 4, 16 ... samples up to the target, each a
// whole render through render_built_scene, so the last pass is the image `manylight render`
// gives with the same options (the command line it reports). A change cancels the pass running.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "film/image.h"
#include "integrators/render_job.h"
#include "scene/scene.h"
#include "view_message.h"

namespace ml {

struct ViewConfig {
    std::string scene_path;  // as given on the command line (for the reproducing command)
    int width = 0, height = 0;
    int threads = 0;
    std::string integrator = "path";         // the refining integrator
    int spp = 64;                            // the refinement's target
    std::map<std::string, std::string> set;  // --set, passed to every render
    std::string save_dir = ".";
    int preview = 2;  // ViewSettings::preview at the start
};

// One message to the clients: a JSON text and, for frames, the RGBA8 pixels after it.
struct ViewMessage {
    std::string text;
    std::vector<uint8_t> rgba;  // empty: a text message only
    bool frame = false;         // frames may be dropped for a slow client
};

class ViewRenderer {
public:
    ViewRenderer(const Scene& scene, ViewConfig config);
    // The render loop; returns after stop(). `broadcast` is called from this thread.
    void run(const std::function<void(std::shared_ptr<const ViewMessage>)>& broadcast);
    void stop();

    // From the clients (any thread). Throw UsageError for values out of range.
    void set_view(const std::array<float, 9>& look_at);
    void reset_view();
    // The scene's viewpoint (eye, target, up) and the settings now.
    const std::array<float, 9>& home() const { return m_home; }
    ViewSettings settings() const;
    // Applies a settings message (apply_view_settings).
    void set_settings(const nlohmann::json& j);
    void request_save();
    // The hello message a new client gets, and the last frame (null before the first).
    std::shared_ptr<const ViewMessage> hello() const;
    std::shared_ptr<const ViewMessage> last_frame() const;

    // A moving frame of `view`: `igi` at 1/divider of the view's width and height (rounded up),
    // each pixel repeated over divider x divider pixels of the view's size; divider 1 is the
    // full-resolution frame. Throws what render_built_scene throws; `cancel` as RenderOptions'.
    struct MovingFrame {
        Image image;  // at the view's size
        RenderFigures figures;
    };
    MovingFrame moving_frame(const std::array<float, 9>& view, const ViewSettings& s, int divider,
                             const std::atomic<bool>* cancel = nullptr) const;

    // The frame message of an image: its status and the pixels in 8-bit sRGB after the exposure.
    std::shared_ptr<const ViewMessage> frame_message(const Image& image, nlohmann::json status,
                                                     float exposure) const;

private:
    RenderOptions options_for(bool moving, const std::array<float, 9>& view, const ViewSettings& s,
                              int spp) const;
    std::string command_line(const std::array<float, 9>& view, const ViewSettings& s,
                             const std::string& output) const;

    const Scene& m_scene;
    ViewConfig m_config;
    std::array<float, 9> m_home;  // the scene's viewpoint

    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::array<float, 9> m_view;
    ViewSettings m_settings;
    uint64_t m_version = 1;    // bumped by every change of the view or of a render setting
    bool m_retonemap = false;  // exposure changed: send the last image again
    bool m_save = false;
    bool m_stop = false;
    std::atomic<bool> m_cancel{false};
    std::shared_ptr<const ViewMessage> m_last_frame;
    Image m_last_image;
    nlohmann::json m_last_status;
    int m_saves = 0;
};

}  // namespace ml
