// The viewer under load (`manylight view`, apps/view_server.cpp): pages that connect while the
// scene still loads, on a machine kept busy, send bursts of moves; every frame each page gets
// must be the scene. Each frame is decoded as the page decodes it (web/viewer.js: a JSON status,
// then width x height RGBA8 pixels) and compared, pixel by pixel, with its view (the status
// names it) rendered here: `igi` through ViewRenderer::moving_frame for the moving frames (which
// test_viewer_frames.cpp checks against igi itself), `path` through render_built_scene for the
// refined ones, tone mapped here to sRGB. A black frame, a frame of another view, a cleared film
// or a torn image fails.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "integrators/render_job.h"
#include "scene/scene.h"
#include "view_renderer.h"
#include "vpl_test_scenes.h"

extern char** environ;

namespace ml {
namespace {

namespace fs = std::filesystem;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;
using View = std::array<float, 9>;

constexpr int kSpp = 4, kThreads = 2;
int g_width = 48, g_height = 32;  // the view's size
constexpr int kPages = 4;         // pages connected at once
constexpr int kBursts = 6;        // bursts of moves each page sends
constexpr int kMoves = 5;         // views in a burst, sent back to back
// Seconds the server waits before loading the scene (MANYLIGHT_TEST_VIEW_LOAD_SECONDS): the
// pages connect meanwhile.
constexpr double kLoadSeconds = 1.5;
constexpr double kDeadlineSeconds = 120;

std::string stress_scene() {
    return R"(LookAt 0 1.2 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 96 ] "integer yresolution" [ 64 ]
Sampler "independent"
WorldBegin
)" + vpl_test::mixed_box();
}

// `manylight view ARGS` as a child process, its standard output and error collected.
class ServerProcess {
public:
    ServerProcess(const std::vector<std::string>& args, const std::vector<std::string>& env) {
        int fds[2];
        if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
        posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
        posix_spawn_file_actions_addclose(&actions, fds[0]);
        posix_spawn_file_actions_addclose(&actions, fds[1]);
        std::vector<std::string> argv_s = {MANYLIGHT_BINARY, "view"};
        argv_s.insert(argv_s.end(), args.begin(), args.end());
        std::vector<char*> argv, envp;
        for (auto& a : argv_s) argv.push_back(a.data());
        argv.push_back(nullptr);
        std::vector<std::string> env_s = env;
        for (char** e = environ; *e; ++e) env_s.emplace_back(*e);
        for (auto& e : env_s) envp.push_back(e.data());
        envp.push_back(nullptr);
        int rc = posix_spawn(&m_pid, MANYLIGHT_BINARY, &actions, nullptr, argv.data(), envp.data());
        posix_spawn_file_actions_destroy(&actions);
        close(fds[1]);
        if (rc != 0) {
            close(fds[0]);
            throw std::runtime_error("posix_spawn failed");
        }
        m_reader = std::thread([this, fd = fds[0]] {
            char buf[4096];
            ssize_t n;
            while ((n = read(fd, buf, sizeof buf)) > 0) {
                std::lock_guard lock(m_mutex);
                m_out.append(buf, size_t(n));
                m_changed.notify_all();
            }
            close(fd);
        });
    }
    ~ServerProcess() {
        if (m_status < 0) {
            kill(m_pid, SIGKILL);
            waitpid(m_pid, nullptr, 0);
        }
        m_reader.join();
    }
    // The port of "open http://127.0.0.1:PORT/", or 0 when it is not printed in time.
    int port(double seconds) {
        static const std::regex address(R"(open http://127\.0\.0\.1:(\d+)/)");
        std::unique_lock lock(m_mutex);
        std::smatch m;
        m_changed.wait_for(lock, std::chrono::duration<double>(seconds),
                           [&] { return std::regex_search(m_out, m, address); });
        return m.empty() ? 0 : std::stoi(m[1]);
    }
    std::string output() {
        std::lock_guard lock(m_mutex);
        return m_out;
    }
    void signal(int sig) { kill(m_pid, sig); }
    // The exit code (128 + the signal if one ended it), or -1 if it has not ended in time.
    int wait(double seconds) {
        auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (m_status < 0 && Clock::now() < end) {
            int status = 0;
            if (waitpid(m_pid, &status, WNOHANG) == m_pid)
                m_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            else
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return m_status;
    }

private:
    pid_t m_pid = -1;
    int m_status = -1;
    std::thread m_reader;
    std::mutex m_mutex;
    std::condition_variable m_changed;
    std::string m_out;
};

// Other work on every core (twice over), as on a shared machine.
class BusyMachine {
public:
    BusyMachine() {
        unsigned n = 2 * std::max(1u, std::thread::hardware_concurrency());
        for (unsigned i = 0; i < n; ++i)
            m_threads.emplace_back([this] {
                volatile uint64_t x = 1;
                while (!m_stop.load(std::memory_order_relaxed)) x = x * 6364136223846793005ull + 1;
            });
    }
    ~BusyMachine() {
        m_stop = true;
        for (auto& t : m_threads) t.join();
    }

private:
    std::atomic<bool> m_stop{false};
    std::vector<std::thread> m_threads;
};

View view_of(const nlohmann::json& j) {
    View v{};
    int k = 0;
    for (const char* key : {"eye", "target", "up"})
        for (const auto& x : j.at(key)) v[k++] = x.get<float>();
    return v;
}

nlohmann::json view_message(const View& v) {
    return {{"type", "view"},
            {"eye", {v[0], v[1], v[2]}},
            {"target", {v[3], v[4], v[5]}},
            {"up", {v[6], v[7], v[8]}}};
}

// The eye turned by `degrees` about the up axis through the target (a drag's orbit).
View orbit(const View& v, float degrees) {
    Vec3 eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]), up = normalize(Vec3(v[6], v[7], v[8]));
    Vec3 d = eye - target;
    Vec3 along = up * dot(d, up), across = d - along, side = cross(up, across);
    float a = degrees * kPi / 180.f;
    Vec3 e = target + along + across * std::cos(a) + side * std::sin(a);
    return {e.x, e.y, e.z, v[3], v[4], v[5], v[6], v[7], v[8]};
}

struct PageFrame {
    nlohmann::json status;
    std::vector<uint8_t> rgba;
};

class Pages;

// One page: a WebSocket client that reads every message, as web/viewer.js does.
class Page : public std::enable_shared_from_this<Page> {
public:
    Page(net::io_context& ioc, int index, Pages& pages)
        : m_ws(ioc), m_timer(ioc), m_index(index), m_pages(pages), m_rng(1234u + unsigned(index)) {}

    void start(int port);
    void send(const nlohmann::json& j) {
        m_out.push_back(j.dump());
        if (m_out.size() == 1) write_next();
    }
    void close() {
        m_closing = true;
        m_timer.cancel();
        m_ws.async_close(websocket::close_code::normal, [self = shared_from_this()](auto) {});
    }
    void fail(const std::string& what);

    int index() const { return m_index; }
    std::vector<std::string> kinds;  // every text message's type, in order
    std::vector<PageFrame> frames;
    std::vector<View> sent;
    std::optional<View> home;
    std::string failure;
    bool converged = false;  // got the final view's converged frame

private:
    void read();
    void on_text(const std::string& text);
    void on_pixels(std::vector<uint8_t> rgba);
    void burst(int b);
    void write_next() {
        m_ws.text(true);
        m_ws.async_write(net::buffer(m_out.front()),
                         [self = shared_from_this()](beast::error_code ec, size_t) {
                             if (ec) return self->fail("write: " + ec.message());
                             self->m_out.pop_front();
                             if (!self->m_out.empty()) self->write_next();
                         });
    }

    websocket::stream<beast::tcp_stream> m_ws;
    beast::flat_buffer m_buffer;
    net::steady_timer m_timer;
    std::deque<std::string> m_out;
    std::optional<nlohmann::json> m_status;  // a frame's status, its pixels due next
    int m_index;
    Pages& m_pages;
    std::mt19937 m_rng;
    bool m_closing = false;
};

// The pages together, on one I/O thread: after their bursts, page 0 sends a last view, and the
// run ends when every page has its converged frame.
class Pages {
    // First: the pages' sockets and timers use it until they are destroyed.
    net::io_context m_ioc;

public:
    Pages(int port, int count) : m_deadline(m_ioc) {
        for (int i = 0; i < count; ++i) pages.push_back(std::make_shared<Page>(m_ioc, i, *this));
        for (auto& p : pages) p->start(port);
        m_deadline.expires_after(std::chrono::seconds(int(kDeadlineSeconds)));
        m_deadline.async_wait([this](beast::error_code ec) {
            if (ec) return;
            for (auto& p : pages)
                if (!p->converged) p->fail("no converged frame of the last view in time");
            m_ioc.stop();
        });
    }
    void run() { m_ioc.run(); }

    void bursts_done() {
        if (++m_done < int(pages.size())) return;
        final_view = orbit(*pages[0]->home, 7.f);
        pages[0]->sent.push_back(*final_view);
        pages[0]->send(view_message(*final_view));
    }
    void page_converged() {
        for (auto& p : pages)
            if (!p->converged && p->failure.empty()) return;
        m_deadline.cancel();
        for (auto& p : pages) p->close();
    }
    void page_failed() {
        m_deadline.cancel();
        m_ioc.stop();
    }

    std::vector<std::shared_ptr<Page>> pages;
    std::optional<View> final_view;

private:
    net::steady_timer m_deadline;
    int m_done = 0;
};

void Page::fail(const std::string& what) {
    if (m_closing || !failure.empty()) return;
    failure = "page " + std::to_string(m_index) + ": " + what;
    m_pages.page_failed();
}

void Page::start(int port) {
    m_ws.next_layer().async_connect(
        tcp::endpoint(net::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)),
        [self = shared_from_this(), port](beast::error_code ec) {
            if (ec) return self->fail("connect: " + ec.message());
            self->m_ws.async_handshake(
                "127.0.0.1:" + std::to_string(port), "/ws", [self](beast::error_code ec) {
                    if (ec) return self->fail("handshake: " + ec.message());
                    self->m_ws.read_message_max(64 << 20);
                    // Page 0 steers before the scene is ready: it must be told to wait, and
                    // stay connected.
                    if (self->m_index == 0) self->send(view_message({0, 1, -4, 0, 0, 0, 0, 1, 0}));
                    self->read();
                });
        });
}

void Page::read() {
    m_ws.async_read(m_buffer, [self = shared_from_this()](beast::error_code ec, size_t) {
        if (ec) {
            if (!self->m_closing) self->fail("read: " + ec.message());
            return;
        }
        auto data = self->m_buffer.data();
        if (self->m_ws.got_text()) {
            self->on_text(beast::buffers_to_string(data));
        } else {
            auto* p = static_cast<const uint8_t*>(data.data());
            self->on_pixels(std::vector<uint8_t>(p, p + data.size()));
        }
        self->m_buffer.consume(self->m_buffer.size());
        if (self->failure.empty()) self->read();
    });
}

void Page::on_text(const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("type"))
        return fail("not a JSON message with a type: " + text);
    if (m_status) return fail("a text message where a frame's pixels were due: " + text);
    const std::string type = j["type"];
    kinds.push_back(type);
    if (type == "loading") return;
    if (type == "error") {
        // Only page 0's view before the hello is refused, and only for that reason.
        if (m_index == 0 && !home &&
            j.value("message", "").find("still loading") != std::string::npos)
            return;
        return fail("error: " + text);
    }
    if (type == "frame") {
        m_status = std::move(j);
        return;
    }
    if (type != "hello") return fail("unexpected message: " + text);
    if (home) return fail("a second hello");
    home = view_of(j.at("home"));
    burst(0);
}

void Page::on_pixels(std::vector<uint8_t> rgba) {
    if (!m_status) return fail("pixels with no frame status before them");
    frames.push_back({std::move(*m_status), std::move(rgba)});
    m_status.reset();
    const nlohmann::json& s = frames.back().status;
    if (!converged && m_pages.final_view && s.value("mode", "") == "converged" &&
        view_of(s.at("view")) == *m_pages.final_view) {
        converged = true;
        m_pages.page_converged();
    }
}

// Burst b: kMoves views back to back (a drag's messages), then a pause of 20 to 250 ms before
// the next, during which the server renders and sends.
void Page::burst(int b) {
    if (b == kBursts) return m_pages.bursts_done();
    std::uniform_real_distribution<float> angle(-25.f, 25.f);
    for (int k = 0; k < kMoves; ++k) {
        sent.push_back(orbit(*home, angle(m_rng)));
        send(view_message(sent.back()));
    }
    m_timer.expires_after(std::chrono::milliseconds(20 + int(m_rng() % 230)));
    m_timer.async_wait([self = shared_from_this(), b](beast::error_code ec) {
        if (!ec) self->burst(b + 1);
    });
}

// Linear radiance to an 8-bit sRGB value, as a display shows it (exposure 0).
int srgb_byte(float v) {
    v = std::clamp(v, 0.f, 1.f);
    float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
    return int(std::lround(255.f * s));
}

// What a frame must show: its view rendered here, tone mapped.
class References {
public:
    References(const std::string& scene_path)
        : m_scene(parse_scene_file(scene_path)), m_viewer(m_scene, config()) {}
    static ViewConfig config() {
        ViewConfig c;
        c.width = g_width;
        c.height = g_height;
        c.threads = kThreads;
        c.spp = kSpp;
        return c;
    }
    const View& home() const { return m_viewer.home(); }
    // The 8-bit sRGB channels (RGB, no alpha) of the frame `status` describes.
    const std::vector<int>& expected(const nlohmann::json& status) {
        const std::string mode = status.at("mode");
        const View view = view_of(status.at("view"));
        const int spp = status.at("spp");
        const int preview = status.value("preview", 1);
        std::string key =
            status.at("view").dump() + mode + std::to_string(spp) + "/" + std::to_string(preview);
        auto it = m_cache.find(key);
        if (it != m_cache.end()) return it->second;
        Image image;
        if (mode == "moving") {
            image = m_viewer.moving_frame(view, m_viewer.settings(), preview).image;
        } else {
            RenderOptions o;
            o.integrator = "path";
            o.spp = spp;
            o.width = g_width;
            o.height = g_height;
            o.threads = kThreads;
            o.look_at = view;
            image = render_built_scene(m_scene, o).image;
        }
        std::vector<int> bytes;
        for (const RGB& p : image.pixels)
            for (int c = 0; c < 3; ++c) bytes.push_back(srgb_byte(p[c]));
        return m_cache[key] = std::move(bytes);
    }

private:
    Scene m_scene;
    ViewRenderer m_viewer;
    std::map<std::string, std::vector<int>> m_cache;
};

class ViewerStress : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("manylight-view-stress-" + std::to_string(getpid()));
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string write_scene(const std::string& text) {
        std::string path = (m_dir / "scene.pbrt").string();
        std::ofstream(path) << text;
        return path;
    }
    fs::path m_dir;
};

// MANYLIGHT_VIEW_STRESS_SCENE=FILE runs it on another scene (the kitchen: a manual check,
// bench/RESULTS.md "Viewer under load"), at MANYLIGHT_VIEW_STRESS_RESOLUTION (WxH).
TEST_F(ViewerStress, PagesConnectingWhileLoadingOnABusyMachineGetTheSceneInEveryFrame) {
    const char* other = std::getenv("MANYLIGHT_VIEW_STRESS_SCENE");
    const std::string scene = other ? std::string(other) : write_scene(stress_scene());
    if (const char* size = std::getenv("MANYLIGHT_VIEW_STRESS_RESOLUTION")) {
        ASSERT_EQ(std::sscanf(size, "%dx%d", &g_width, &g_height), 2);
    }
    // What each page received, kept past the pages (whose sockets die with their I/O context).
    struct PageResult {
        int index;
        std::vector<std::string> kinds;
        std::vector<PageFrame> frames;
        std::vector<View> sent;
        std::optional<View> home;
        std::string failure;
        bool converged;
    };
    std::vector<PageResult> keep;
    {
        BusyMachine busy;
        ServerProcess server(
            {scene, "--port", "0", "--resolution", fmt::format("{}x{}", g_width, g_height), "--spp",
             std::to_string(kSpp), "--threads", std::to_string(kThreads), "--output-dir",
             m_dir.string(), "--exit-after", std::to_string(int(kDeadlineSeconds) + 30)},
            {fmt::format("MANYLIGHT_TEST_VIEW_LOAD_SECONDS={}", kLoadSeconds)});
        const int port = server.port(30);
        ASSERT_GT(port, 0) << server.output();
        Pages run(port, kPages);
        run.run();
        for (const auto& p : run.pages)
            keep.push_back(
                {p->index(), p->kinds, p->frames, p->sent, p->home, p->failure, p->converged});
        server.signal(SIGINT);
        EXPECT_EQ(server.wait(30), 0) << server.output();
        EXPECT_NE(server.output().find("manylight view: stopped"), std::string::npos)
            << server.output();
    }
    References refs(scene);
    size_t total = 0;
    for (const auto& page : keep) {
        SCOPED_TRACE("page " + std::to_string(page.index));
        EXPECT_EQ(page.failure, "");
        // Connected while the scene loaded: told so first, then the hello.
        ASSERT_GE(page.kinds.size(), 2u);
        EXPECT_EQ(page.kinds[0], "loading");
        size_t hello = page.index == 0 ? 2 : 1;
        if (page.index == 0) {
            EXPECT_EQ(page.kinds[1], "error");
        }
        ASSERT_GT(page.kinds.size(), hello);
        EXPECT_EQ(page.kinds[hello], "hello");
        ASSERT_TRUE(page.home);
        EXPECT_EQ(*page.home, refs.home());
        EXPECT_TRUE(page.converged);
        ASSERT_FALSE(page.frames.empty());
        // Every view a frame shows was the scene's own or one a page sent.
        std::vector<View> views = {refs.home()};
        for (const auto& p : keep) views.insert(views.end(), p.sent.begin(), p.sent.end());
        for (size_t f = 0; f < page.frames.size(); ++f) {
            const PageFrame& frame = page.frames[f];
            const nlohmann::json& s = frame.status;
            SCOPED_TRACE("frame " + std::to_string(f) + ": " + s.dump());
            ASSERT_EQ(s.at("width"), g_width);
            ASSERT_EQ(s.at("height"), g_height);
            ASSERT_EQ(frame.rgba.size(), size_t(g_width) * g_height * 4);
            const View view = view_of(s.at("view"));
            EXPECT_NE(std::find(views.begin(), views.end(), view), views.end());
            const std::vector<int>& want = refs.expected(s);
            int64_t sum = 0, want_sum = 0, worst = 0, opaque = 0;
            for (size_t i = 0; i < size_t(g_width) * g_height; ++i) {
                opaque += frame.rgba[4 * i + 3] == 255;
                for (int c = 0; c < 3; ++c) {
                    int got = frame.rgba[4 * i + size_t(c)], w = want[3 * i + size_t(c)];
                    sum += got;
                    want_sum += w;
                    worst = std::max<int64_t>(worst, std::abs(got - w));
                }
            }
            // The view's image is far from black, and the frame is that image (8-bit rounding
            // of the page's table apart).
            ASSERT_GT(want_sum, int64_t(g_width) * g_height * 3 * 10);
            EXPECT_EQ(opaque, int64_t(g_width) * g_height);
            EXPECT_LE(worst, 2) << "frame sum " << sum << ", its view's " << want_sum;
            ++total;
        }
    }
    // Moves were shown, and the last view converged on every page.
    EXPECT_GE(total, size_t(2 * kPages));
    std::printf("viewer stress: %zu frames checked on %d pages\n", total, kPages);
}

TEST_F(ViewerStress, StopWhileTheSceneLoadsWaitsForTheLoadThenStops) {
    const std::string scene = write_scene(stress_scene());
    ServerProcess server({scene, "--port", "0", "--threads", "1"},
                         {"MANYLIGHT_TEST_VIEW_LOAD_SECONDS=1"});
    ASSERT_GT(server.port(30), 0) << server.output();
    server.signal(SIGINT);
    EXPECT_EQ(server.wait(60), 0) << server.output();
    EXPECT_NE(server.output().find("stopping once the scene has loaded"), std::string::npos)
        << server.output();
    EXPECT_NE(server.output().find("manylight view: stopped"), std::string::npos)
        << server.output();
}

TEST_F(ViewerStress, ASceneErrorWhileServingEndsTheServerWithTheMessage) {
    const std::string good = stress_scene();
    const std::string scene = write_scene(good + "Shape \"nosuchshape\"\n");
    const auto bad_line = std::count(good.begin(), good.end(), '\n') + 1;
    ServerProcess server({scene, "--port", "0", "--threads", "1"}, {});
    EXPECT_EQ(server.wait(60), 1) << server.output();
    EXPECT_NE(server.output().find(fmt::format("scene.pbrt:{}:", bad_line)), std::string::npos)
        << server.output();
    EXPECT_EQ(server.output().find("manylight view: stopped"), std::string::npos)
        << server.output();
}

}  // namespace
}  // namespace ml
