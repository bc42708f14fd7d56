#include "view_server.h"

#include <fmt/format.h>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <csignal>
#include <cstdio>
#include <deque>
#include <mutex>
#include <set>
#include <string_view>
#include <thread>

#include "core/error.h"

namespace ml {

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

constexpr size_t kMaxRequestBytes = 8 * 1024;   // an HTTP request, headers and body
constexpr size_t kMaxMessageBytes = 16 * 1024;  // a message from a page
constexpr size_t kMaxQueuedFrames = 2;  // frames waiting for a slow page; older ones are dropped

class WsSession;

// What every session shares: the renderer (null while the scene loads) and the open WebSockets.
// Touched only on the I/O thread (the server runs one).
struct Hub {
    ViewRenderer* renderer = nullptr;
    std::shared_ptr<const ViewMessage> loading;  // what a page gets until the scene is ready
    std::set<std::shared_ptr<WsSession>> sessions;
};

std::shared_ptr<const ViewMessage> text_message(const nlohmann::json& j) {
    auto msg = std::make_shared<ViewMessage>();
    msg->text = j.dump();
    return msg;
}

class WsSession : public std::enable_shared_from_this<WsSession> {
public:
    WsSession(tcp::socket socket, Hub& hub) : m_ws(std::move(socket)), m_hub(hub) {}

    void run(http::request<http::string_body> request) {
        m_ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        m_ws.read_message_max(kMaxMessageBytes);
        m_ws.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
            if (ec) return;
            self->m_hub.sessions.insert(self);
            if (self->m_hub.renderer)
                self->greet();
            else
                self->send(self->m_hub.loading);
            self->read();
        });
    }

    // The scene's hello and its last frame, if any: on connecting, or once the scene is ready.
    void greet() {
        send(m_hub.renderer->hello());
        if (auto frame = m_hub.renderer->last_frame()) send(frame);
    }

    void send(std::shared_ptr<const ViewMessage> msg) {
        if (m_closing) return;
        if (msg->frame) {
            // Drop frames a slow page has not started to receive: it gets the newest.
            size_t frames = m_writing && m_current->frame ? 1 : 0;
            for (auto& m : m_queue) frames += m->frame;
            if (frames >= kMaxQueuedFrames)
                for (auto it = m_queue.begin(); it != m_queue.end(); ++it)
                    if ((*it)->frame) {
                        m_queue.erase(it);
                        break;
                    }
        }
        m_queue.push_back(std::move(msg));
        if (!m_writing) write_next();
    }

private:
    void read() {
        m_ws.async_read(m_buffer, [self = shared_from_this()](beast::error_code ec, size_t) {
            self->on_read(ec);
        });
    }

    void on_read(beast::error_code ec) {
        if (ec) return leave();  // the page went away, or sent too much: this connection only
        std::string text = beast::buffers_to_string(m_buffer.data());
        m_buffer.consume(m_buffer.size());
        std::string problem = m_ws.got_text() ? handle(text) : "binary messages are not accepted";
        if (!problem.empty()) {
            std::fprintf(stderr, "manylight view: closing a connection: %s\n", problem.c_str());
            m_closing = true;
            m_queue.clear();
            m_hub.sessions.erase(shared_from_this());
            if (m_writing) return;  // the write in flight ends, then the socket goes
            websocket::close_reason reason(websocket::close_code::policy_error);
            reason.reason = problem.substr(0, 120);
            m_ws.async_close(reason, [self = shared_from_this()](beast::error_code) {});
            return;
        }
        read();
    }

    // Acts on a page's message; returns what is wrong with it (empty: nothing).
    std::string handle(const std::string& text) {
        try {
            ViewRequest r = decode_view_request(text);
            if (!m_hub.renderer) {
                // Nothing to steer yet: the page is told, and stays connected.
                send(text_message(
                    {{"type", "error"}, {"message", "the scene is still loading: wait for it"}}));
                return "";
            }
            switch (r.kind) {
                case ViewRequest::Kind::View:
                    m_hub.renderer->set_view(r.look_at);
                    break;
                case ViewRequest::Kind::Settings:
                    m_hub.renderer->set_settings(r.settings);
                    break;
                case ViewRequest::Kind::Reset:
                    m_hub.renderer->reset_view();
                    break;
                case ViewRequest::Kind::Save:
                    m_hub.renderer->request_save();
                    break;
            }
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    }

    // The message in flight is held apart from the queue, which a bad message or a page that
    // leaves clears meanwhile: the writes' buffers stay alive until they end.
    void write_next() {
        if (m_queue.empty()) return;
        m_writing = true;
        m_current = std::move(m_queue.front());
        m_queue.pop_front();
        m_ws.text(true);
        m_ws.async_write(
            net::buffer(m_current->text),
            [self = shared_from_this()](beast::error_code ec, size_t) { self->after_text(ec); });
    }

    void after_text(beast::error_code ec) {
        if (ec) return after_write(ec);
        if (m_current->rgba.empty()) return after_write({});
        m_ws.binary(true);
        m_ws.async_write(
            net::buffer(m_current->rgba),
            [self = shared_from_this()](beast::error_code ec, size_t) { self->after_write(ec); });
    }

    void after_write(beast::error_code ec) {
        m_writing = false;
        m_current.reset();
        if (ec) return leave();
        if (m_closing) {
            m_ws.async_close(websocket::close_code::policy_error,
                             [self = shared_from_this()](beast::error_code) {});
            return;
        }
        write_next();
    }

    void leave() {
        m_closing = true;
        m_queue.clear();
        m_hub.sessions.erase(shared_from_this());
    }

    websocket::stream<beast::tcp_stream> m_ws;
    beast::flat_buffer m_buffer;
    Hub& m_hub;
    std::deque<std::shared_ptr<const ViewMessage>> m_queue;
    std::shared_ptr<const ViewMessage> m_current;  // being written
    bool m_writing = false, m_closing = false;
};

// Answers a GET from the embedded files only; the request's path is compared with their names
// and never reaches the file system.
http::response<http::string_body> respond(const http::request<http::string_body>& req) {
    auto plain = [&](http::status status, std::string body) {
        http::response<http::string_body> res{status, req.version()};
        res.set(http::field::content_type, "text/plain; charset=utf-8");
        res.keep_alive(req.keep_alive());
        res.body() = std::move(body);
        res.prepare_payload();
        return res;
    };
    if (req.method() != http::verb::get && req.method() != http::verb::head)
        return plain(http::status::method_not_allowed, "only GET\n");
    std::string_view target(req.target().data(), req.target().size());
    target = target.substr(0, target.find('?'));
    if (target == "/") target = "/index.html";
    unsigned long count = 0;
    const EmbeddedFile* files = embedded_web_files(&count);
    for (unsigned long i = 0; i < count; ++i) {
        if (target != files[i].path) continue;
        http::response<http::string_body> res{http::status::ok, req.version()};
        res.set(http::field::content_type, files[i].content_type);
        res.set(http::field::cache_control, "no-store");
        res.set("Content-Security-Policy",
                "default-src 'self'; connect-src 'self'; img-src 'self' data: blob:");
        res.set("X-Content-Type-Options", "nosniff");
        res.keep_alive(req.keep_alive());
        if (req.method() == http::verb::get)
            res.body().assign(reinterpret_cast<const char*>(files[i].data), files[i].size);
        res.prepare_payload();
        return res;
    }
    return plain(http::status::not_found, "not found\n");
}

class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(tcp::socket socket, Hub& hub) : m_stream(std::move(socket)), m_hub(hub) {}
    void run() { read(); }

private:
    void read() {
        m_parser.emplace();
        m_parser->header_limit(kMaxRequestBytes);
        m_parser->body_limit(kMaxRequestBytes);
        m_stream.expires_after(std::chrono::seconds(30));
        http::async_read(
            m_stream, m_buffer, *m_parser,
            [self = shared_from_this()](beast::error_code ec, size_t) { self->on_read(ec); });
    }

    void on_read(beast::error_code ec) {
        if (ec) {
            beast::error_code ignored;
            m_stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
            return;
        }
        http::request<http::string_body> req = m_parser->release();
        if (websocket::is_upgrade(req) && req.target() == "/ws") {
            m_stream.expires_never();
            std::make_shared<WsSession>(m_stream.release_socket(), m_hub)->run(std::move(req));
            return;
        }
        auto res = std::make_shared<http::response<http::string_body>>(respond(req));
        http::async_write(
            m_stream, *res, [self = shared_from_this(), res](beast::error_code ec, size_t) {
                if (ec || res->need_eof()) {
                    beast::error_code ignored;
                    self->m_stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
                    return;
                }
                self->read();
            });
    }

    beast::tcp_stream m_stream;
    beast::flat_buffer m_buffer;
    std::optional<http::request_parser<http::string_body>> m_parser;
    Hub& m_hub;
};

void accept(tcp::acceptor& acceptor, Hub& hub) {
    acceptor.async_accept([&acceptor, &hub](beast::error_code ec, tcp::socket socket) {
        if (!acceptor.is_open()) return;
        if (!ec) std::make_shared<HttpSession>(std::move(socket), hub)->run();
        accept(acceptor, hub);
    });
}

}  // namespace

void serve_viewer(const ViewLoader& load, const ViewServerOptions& opt) {
    net::io_context ioc(1);
    beast::error_code ec;
    net::ip::address address = net::ip::make_address(opt.bind, ec);
    if (ec) throw UsageError("--bind: not an IP address: " + opt.bind);
    tcp::acceptor acceptor(ioc);
    tcp::endpoint endpoint(address, static_cast<unsigned short>(opt.port));
    acceptor.open(endpoint.protocol(), ec);
    if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) acceptor.bind(endpoint, ec);
    if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
    if (ec)
        throw UsageError(
            fmt::format("cannot listen on {}:{}: {}", opt.bind, opt.port, ec.message()));
    Hub hub;
    hub.loading = text_message({{"type", "loading"}, {"scene", opt.scene}});
    accept(acceptor, hub);

    // The loader thread builds the renderer, then runs its loop; the I/O thread (this one)
    // serves the pages meanwhile. `state` is shared by both.
    struct {
        std::mutex mutex;
        bool stopping = false, loaded = false;
        std::unique_ptr<ViewRenderer> renderer;
        std::exception_ptr failure;
    } state;
    net::signal_set signals(ioc, SIGINT, SIGTERM);
    auto shutdown = [&] {
        {
            std::lock_guard lock(state.mutex);
            state.stopping = true;
            if (state.renderer) state.renderer->stop();
        }
        beast::error_code ignored;
        acceptor.close(ignored);
        // A second Ctrl-C (while the scene still loads, which cannot be cut short) ends the
        // process at once.
        signals.clear(ignored);
        ioc.stop();
    };
    signals.async_wait([&](beast::error_code e, int) {
        if (!e) shutdown();
    });
    net::steady_timer timer(ioc);
    if (opt.exit_after > 0) {
        timer.expires_after(std::chrono::milliseconds(int64_t(opt.exit_after * 1000)));
        timer.async_wait([&](beast::error_code e) {
            if (!e) shutdown();
        });
    }

    // The address once Ctrl-C is handled: a stop right after it is a clean one.
    const tcp::endpoint bound = acceptor.local_endpoint();
    std::string host = bound.address().is_v6() ? "[" + bound.address().to_string() + "]"
                                               : bound.address().to_string();
    std::printf("manylight view: open http://%s:%d/ (Ctrl-C stops)\n", host.c_str(),
                int(bound.port()));
    std::fflush(stdout);

    std::thread render_thread([&] {
        std::unique_ptr<ViewRenderer> renderer;
        try {
            renderer = load();
        } catch (...) {
            std::lock_guard lock(state.mutex);
            state.failure = std::current_exception();
            state.loaded = true;
            net::post(ioc, shutdown);
            return;
        }
        ViewRenderer* r = renderer.get();
        {
            std::lock_guard lock(state.mutex);
            state.loaded = true;
            if (state.stopping) return;
            state.renderer = std::move(renderer);
        }
        // The pages that connected while the scene loaded get its hello now; posted before the
        // loop's first frame, so they get it first (the I/O thread runs handlers in order).
        net::post(ioc, [&hub, r] {
            hub.renderer = r;
            for (const auto& s : std::vector(hub.sessions.begin(), hub.sessions.end())) s->greet();
        });
        r->run([&](std::shared_ptr<const ViewMessage> msg) {
            net::post(ioc, [&hub, msg] {
                for (const auto& s : std::vector(hub.sessions.begin(), hub.sessions.end()))
                    s->send(msg);
            });
        });
    });
    ioc.run();
    {
        std::lock_guard lock(state.mutex);
        if (!state.loaded)
            std::printf(
                "manylight view: stopping once the scene has loaded (Ctrl-C again: at once)\n");
        std::fflush(stdout);
    }
    render_thread.join();
    if (state.failure) std::rethrow_exception(state.failure);
    std::printf("manylight view: stopped\n");
}

}  // namespace ml
