// The viewer's HTTP and WebSocket server (Boost.Beast): serves the page compiled into the
// program (web/, embedded by CMake; no request path reaches the file system) and speaks to
// every connected page over a WebSocket at /ws. Safe by default: it listens where it is told
// (127.0.0.1 unless --bind says otherwise), requests and messages are bounded, a malformed
// message closes that connection only, any number of pages may watch, and a page that goes
// away leaves the server running.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "view_renderer.h"

namespace ml {

struct ViewServerOptions {
    std::string scene;  // the scene's name, for the pages that connect while it loads
    std::string bind = "127.0.0.1";
    int port = 8080;        // 0: any free port
    double exit_after = 0;  // seconds; > 0: stop by itself after this long (tests)
};

// Makes the renderer: loads the scene and builds it (seconds to minutes for a large one).
using ViewLoader = std::function<std::unique_ptr<ViewRenderer>()>;

// Listens, prints the address to open, and serves until SIGINT or SIGTERM (or exit_after). The
// scene loads meanwhile on a thread of its own (`load`), which then runs the renderer's loop:
// pages that connect before it is ready are told that it loads (a "loading" message), and get
// the hello and the frames once it is. Throws UsageError when it cannot listen, and what `load`
// throws (after closing the server). A stop while the scene loads waits for the load to end.
void serve_viewer(const ViewLoader& load, const ViewServerOptions& options);

// The files the page is made of, compiled into the program (web_files.cpp, generated).
struct EmbeddedFile {
    const char* path;          // "/index.html"
    const char* content_type;  // "text/html; charset=utf-8"
    const unsigned char* data;
    unsigned long size;
};
const EmbeddedFile* embedded_web_files(unsigned long* count);

}  // namespace ml
