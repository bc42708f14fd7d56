// `import manylight`: the renderer from Python (pybind11). render() runs what `manylight render`
// runs, load_scene and render_loaded_scene (integrators/render_job.h), with the same options and
// the same defaults (an argument left out is an option not given), so the image for a seed is
// the command line's. The render runs on a thread of its own; the caller's thread, without the
// GIL, waits for it and every kPollInterval checks for Ctrl-C (PyErr_CheckSignals) and calls the
// progress callback. Ctrl-C, or an exception from the callback, cancels the render through
// RenderOptions::cancel (RenderContext::cancel), which stops it as a spent time limit does; the
// exception is raised once the render has stopped, and no image is returned.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "film/image.h"
#include "integrators/registry.h"
#include "integrators/render_job.h"

namespace py = pybind11;

namespace ml {
namespace {

constexpr std::chrono::milliseconds kPollInterval{50};

// The module's exception and warning types, made at import.
PyObject* g_error = nullptr;           // manylight.Error(Exception)
PyObject* g_input_error = nullptr;     // manylight.InputError(Error): a bad scene, with its place
PyObject* g_usage_error = nullptr;     // manylight.UsageError(Error, ValueError): a bad argument
PyObject* g_render_warning = nullptr;  // manylight.RenderWarning(UserWarning)

// One render at a time in a process: the ray counters and the thread limit are the process's.
std::mutex g_render_mutex;

// The text --set would take for a setting's value: bools as true/false, floats in Python's
// shortest form that reads back as the same number.
std::string setting_text(const std::string& key, const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
    if (py::isinstance<py::float_>(v)) return py::repr(v).cast<std::string>();
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    throw UsageError("settings[\"" + key + "\"]: expected a bool, int, float or str, got " +
                     py::str(py::type::of(v).attr("__name__")).cast<std::string>());
}

// A setting's default as a Python value of its type.
py::object setting_value(const SettingDefault& d) {
    if (d.type == "int") return py::int_(std::stoll(d.value));
    if (d.type == "float") return py::float_(std::stod(d.value));
    if (d.type == "bool") return py::bool_(d.value == "true");
    return py::str(d.value);
}

template <typename T>
void check(bool ok, const char* name, const char* expected, const T& got) {
    if (!ok) throw UsageError(fmt::format("{}: expected {}, got {}", name, expected, got));
}

// The arguments as the command line's options (apps/render_command.cpp: run_render), with the
// checks its validators make (apps/options.cpp).
RenderOptions options_from(const std::optional<std::string>& integrator, std::optional<int> spp,
                           std::optional<std::tuple<int, int>> resolution,
                           std::optional<long long> seed, std::optional<double> time_limit,
                           const std::optional<py::dict>& settings, std::optional<int> max_depth,
                           const std::optional<std::string>& sampler, std::optional<int> threads,
                           const std::optional<std::vector<float>>& look_at,
                           const std::optional<std::string>& checkpoint,
                           std::optional<double> checkpoint_every,
                           const std::optional<std::string>& resume) {
    RenderOptions o;
    if (integrator) o.integrator = *integrator;
    if (spp) {
        check(*spp > 0, "spp", "a positive integer", *spp);
        o.spp = *spp;
    }
    if (resolution) {
        auto [w, h] = *resolution;
        check(w > 0 && h > 0 && w <= 65536 && h <= 65536, "resolution",
              "(width, height), both from 1 to 65536", fmt::format("({}, {})", w, h));
        o.width = w;
        o.height = h;
    }
    if (seed) {
        check(*seed >= 0, "seed", "a non-negative integer", *seed);
        o.seed = uint64_t(*seed);
    }
    if (time_limit) {
        check(std::isfinite(*time_limit) && *time_limit > 0, "time_limit",
              "a positive number of seconds", *time_limit);
        o.time_limit = *time_limit;
    }
    if (max_depth) {
        check(*max_depth >= 0, "max_depth", "a non-negative integer", *max_depth);
        o.max_depth = *max_depth;
    }
    if (sampler) {
        check(*sampler == "independent" || *sampler == "stratified" || *sampler == "sobol",
              "sampler", "independent, stratified or sobol", "\"" + *sampler + "\"");
        o.sampler = *sampler;
    }
    if (threads) {
        check(*threads > 0, "threads", "a positive integer", *threads);
        o.threads = *threads;
    }
    if (look_at) {
        check(look_at->size() == 9, "look_at", "9 numbers (eye, target, up)", look_at->size());
        std::array<float, 9> v;
        std::copy(look_at->begin(), look_at->end(), v.begin());
        o.look_at = v;
    }
    if (checkpoint) o.checkpoint = *checkpoint;
    if (checkpoint_every) {
        check(std::isfinite(*checkpoint_every) && *checkpoint_every >= 0, "checkpoint_every",
              "a number of seconds, 0 or more", *checkpoint_every);
        o.checkpoint_every = *checkpoint_every;
    }
    if (resume) o.resume = *resume;
    if (settings)
        for (auto [k, v] : *settings) {
            std::string key = py::str(k).cast<std::string>();
            o.set[key] = setting_text(key, v);
        }
    return o;
}

py::array_t<float> to_array(const Image& image) {
    py::array_t<float> a({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)});
    float* dst = a.mutable_data();
    for (const RGB& p : image.pixels) {
        *dst++ = p.r;
        *dst++ = p.g;
        *dst++ = p.b;
    }
    return a;
}

Image from_array(const py::array_t<float, py::array::c_style | py::array::forcecast>& a) {
    if (a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) < 1 || a.shape(1) < 1)
        throw UsageError("image: expected an array of shape (height, width, 3)");
    Image image(int(a.shape(1)), int(a.shape(0)));
    const float* src = a.data();
    for (RGB& p : image.pixels) {
        p = {src[0], src[1], src[2]};
        src += 3;
    }
    return image;
}

// Runs the render on a thread of its own; this thread, without the GIL, polls for Ctrl-C and
// calls `progress`. A Python exception (KeyboardInterrupt, or the callback's) cancels the render
// and is raised once it has stopped.
RenderOutput run_render(const std::string& path, RenderOptions o, const py::object& progress) {
    std::atomic<bool> cancel{false};
    std::atomic<double> fraction{0};
    o.cancel = &cancel;
    o.on_progress = [&fraction](double f) {
        f = std::min(f, 1.0);  // a time limit's fraction passes 1 as the last round ends
        double seen = fraction.load(std::memory_order_relaxed);
        while (f > seen && !fraction.compare_exchange_weak(seen, f, std::memory_order_relaxed)) {
        }
    };
    RenderOutput out;
    std::exception_ptr failure;
    PyObject *type = nullptr, *value = nullptr, *trace = nullptr;  // the Python error, if any
    {
        py::gil_scoped_release no_gil;
        std::lock_guard<std::mutex> one_at_a_time(g_render_mutex);
        std::mutex mutex;
        std::condition_variable finished_cv;
        bool finished = false;
        std::thread worker([&] {
            try {
                out = render_loaded_scene(load_scene(path), o);
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mutex);
            finished = true;
            finished_cv.notify_one();
        });
        double reported = 0;
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(mutex);
                if (finished_cv.wait_for(lock, kPollInterval, [&] { return finished; })) break;
            }
            if (type) continue;  // cancelled: wait for the render to stop
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) {
                PyErr_Fetch(&type, &value, &trace);
                cancel = true;
                continue;
            }
            double f = fraction.load(std::memory_order_relaxed);
            if (progress.is_none() || f <= reported) continue;
            reported = f;
            try {
                progress(f);
            } catch (py::error_already_set& e) {
                e.restore();
                PyErr_Fetch(&type, &value, &trace);
                cancel = true;
            } catch (const std::exception& e) {
                PyErr_SetString(PyExc_RuntimeError, e.what());
                PyErr_Fetch(&type, &value, &trace);
                cancel = true;
            }
        }
        worker.join();
    }
    if (type) {
        PyErr_Restore(type, value, trace);
        throw py::error_already_set();
    }
    if (failure) std::rethrow_exception(failure);
    if (!progress.is_none()) progress(1.0);
    return out;
}

py::tuple render(const py::object& scene, const std::optional<std::string>& integrator,
                 std::optional<int> spp, std::optional<std::tuple<int, int>> resolution,
                 std::optional<long long> seed, std::optional<double> time_limit,
                 const std::optional<py::dict>& settings, std::optional<int> max_depth,
                 const std::optional<std::string>& sampler, std::optional<int> threads,
                 const std::optional<std::vector<float>>& look_at, const py::object& progress,
                 const py::object& checkpoint, std::optional<double> checkpoint_every,
                 const py::object& resume) {
    auto fspath = [](const py::object& p) -> std::optional<std::string> {
        if (p.is_none()) return std::nullopt;
        return py::str(py::module_::import("os").attr("fspath")(p)).cast<std::string>();
    };
    std::string path = fspath(scene).value_or("");
    if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
        throw UsageError("progress: expected a callable taking the fraction done");
    RenderOptions o =
        options_from(integrator, spp, resolution, seed, time_limit, settings, max_depth, sampler,
                     threads, look_at, fspath(checkpoint), checkpoint_every, fspath(resume));
    RenderOutput out = run_render(path, std::move(o), progress);
    for (const std::string& w : out.figures.warnings)
        if (PyErr_WarnEx(g_render_warning, w.c_str(), 1) != 0) throw py::error_already_set();
    py::object stats = py::module_::import("json").attr("loads")(out.figures.to_json().dump());
    return py::make_tuple(to_array(out.image), stats);
}

py::dict integrators() {
    py::dict all;
    for (const IntegratorInfo& info : integrator_registry()) {
        py::dict settings;
        for (const SettingDefault& d : integrator_settings(info))
            settings[py::str(d.key)] = setting_value(d);
        py::dict entry;
        entry["summary"] = info.summary;
        entry["settings"] = settings;
        all[py::str(info.name)] = entry;
    }
    return all;
}

// An exception type manylight.NAME deriving from `bases`, added to the module.
PyObject* add_exception(py::module_& m, const char* name, const char* doc, PyObject* bases) {
    std::string full = std::string("manylight.") + name;
    PyObject* type = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases, nullptr);
    if (!type) throw py::error_already_set();
    m.attr(name) = py::handle(type);  // the module keeps a reference; `type` keeps ours
    return type;
}

void translate(std::exception_ptr p) {
    try {
        if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
        py::object error = py::reinterpret_borrow<py::object>(g_input_error)(e.formatted());
        error.attr("file") = e.loc().file;
        error.attr("line") = e.loc().line;
        error.attr("column") = e.loc().column;
        error.attr("message") = std::string(e.what());
        PyErr_SetObject(g_input_error, error.ptr());
    } catch (const UsageError& e) {
        PyErr_SetString(g_usage_error, e.what());
    } catch (const Error& e) {
        PyErr_SetString(g_error, e.what());
    }
}

}  // namespace
}  // namespace ml

PYBIND11_MODULE(manylight, m) {
    using namespace ml;
    m.doc() =
        "manylight: a many-light renderer for pbrt-v4 scenes. render() runs what `manylight "
        "render` runs; integrators() lists the integrators, their settings and defaults.";
    g_error =
        add_exception(m, "Error", "The base of every error manylight raises.", PyExc_Exception);
    g_input_error = add_exception(
        m, "InputError",
        "Bad input: a scene, mesh, image or parameter. str() is `file:line:col: message` with "
        "the line and a caret; attributes file, line, column (0: unknown) and message.",
        g_error);
    py::tuple usage_bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
    g_usage_error = add_exception(m, "UsageError",
                                  "A bad argument or setting (the command line's exit status 2).",
                                  usage_bases.ptr());
    g_render_warning =
        add_exception(m, "RenderWarning",
                      "A setting or result the render warns about (the command line's "
                      "`manylight: warning:` lines).",
                      PyExc_UserWarning);
    py::register_exception_translator(translate);

    m.def("render", &render, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("integrator") = py::none(), py::arg("spp") = py::none(),
          py::arg("resolution") = py::none(), py::arg("seed") = py::none(),
          py::arg("time_limit") = py::none(), py::arg("settings") = py::none(),
          py::arg("max_depth") = py::none(), py::arg("sampler") = py::none(),
          py::arg("threads") = py::none(), py::arg("look_at") = py::none(),
          py::arg("progress") = py::none(), py::arg("checkpoint") = py::none(),
          py::arg("checkpoint_every") = py::none(), py::arg("resume") = py::none(),
          R"(Renders a pbrt-v4 scene as `manylight render` does; returns (image, stats).

scene: the scene file (str or path); None renders the built-in Cornell box.
Every other argument is a command-line option, and one left out (None) is an option not
given, so the defaults are the command line's: the scene's own Film, Sampler and Integrator
where it has them, else path tracing at 16 samples per pixel, seed 0.
  integrator   --integrator NAME (integrators() lists them)
  spp          --spp N;  resolution: (width, height), --resolution WxH
  seed         --seed N;  time_limit: --time-limit SECONDS
  settings     {"NAME.KEY": value}, each --set NAME.KEY=VALUE (bool, int, float or str)
  max_depth    --max-depth;  sampler: --sampler;  threads: --threads (default all cores)
  look_at      9 numbers, --look-at EX EY EZ TX TY TZ UX UY UZ
  checkpoint   --checkpoint FILE (str or path): the render's state, saved every
               checkpoint_every seconds (--checkpoint-every, default 60), at the end and
               when cancelled;  resume: --resume FILE, continue the render saved there
  progress     a callable given the fraction done (0 to 1), from this thread, at most
               every 50 ms and once with 1.0 at the end; an exception it raises cancels the
               render and is raised here.
image: float32 numpy array (height, width, 3), linear RGB, top row first.
stats: the --stats object as a dict.
Ctrl-C cancels the render (saving the checkpoint, if asked) and raises KeyboardInterrupt. Errors: InputError (with the scene
file's place), UsageError, Error. Warnings: RenderWarning. One render at a time per process
(the GIL is released while it runs).)");
    m.def("integrators", &integrators,
          "A dict: integrator name -> {\"summary\": str, \"settings\": {\"NAME.KEY\": default}}, "
          "the settings each reads when nothing is set, with its defaults.");
    m.def(
        "read_image",
        [](const std::filesystem::path& path) { return to_array(read_image(path.string())); },
        py::arg("path"),
        "Reads an image (EXR, PFM, PNG, ...: whatever OpenImageIO reads) as a float32 array "
        "(height, width, 3).");
    m.def(
        "write_image",
        [](const std::filesystem::path& path,
           const py::array_t<float, py::array::c_style | py::array::forcecast>& image) {
            write_image(path.string(), from_array(image));
        },
        py::arg("path"), py::arg("image"),
        "Writes a (height, width, 3) array as .exr (half float), .pfm (float) or .png "
        "(tone-mapped sRGB), as `manylight render -o` does.");
}
