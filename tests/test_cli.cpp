// The command line as users and scripts meet it: exit codes, messages, no partial output.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "film/image.h"
#include "integrators/registry.h"

namespace fs = std::filesystem;

namespace {

struct Result {
    int code = -1;
    std::string output;
};

Result run(const std::string& args) {
    std::string cmd = std::string(MANYLIGHT_BINARY) + " " + args + " 2>&1";
    Result r;
    FILE* p = popen(cmd.c_str(), "r");
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("manylight-cli-" + std::to_string(::getpid()) + "-" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name)) << text;
        return path(name);
    }
    // The render must fail with exit 1, say where, and leave no image behind.
    void expect_input_error(const std::string& args, const std::string& where) {
        std::string out = path("out.exr");
        Result r = run("render " + args + " -q -o " + out);
        EXPECT_EQ(r.code, 1) << r.output;
        EXPECT_NE(r.output.find(where), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(out));
        for (auto& e : fs::directory_iterator(m_dir))
            EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
    }
    fs::path m_dir;
};

const char* kTinyScene = R"(LookAt 0 0 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
LightSource "point" "rgb I" [ 1 1 1 ] "point3 from" [ 0 0 -2 ]
Shape "sphere" "float radius" [ 1 ]
)";

}  // namespace

TEST_F(Cli, RendersASceneAndWritesStats) {
    std::string scene = write("tiny.pbrt", kTinyScene);
    Result r =
        run("render " + scene + " --spp 2 -q -o " + path("a.exr") + " --stats " + path("s.json"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(path("a.exr")));
    std::ifstream js(path("s.json"));
    nlohmann::json stats = nlohmann::json::parse(js);  // throws unless it is JSON
    EXPECT_EQ(stats.at("integrator"), "path");
    EXPECT_EQ(stats.at("spp"), 2);
    EXPECT_EQ(stats.at("resolution"), nlohmann::json({8, 8}));
    EXPECT_GE(stats.at("threads").get<int>(), 1);
    EXPECT_GE(stats.at("seconds").at("render").get<double>(), 0.0);
    EXPECT_EQ(stats.at("rays").at("camera"), 8 * 8 * 2);  // one per pixel sample
    EXPECT_GT(stats.at("rays_per_second").get<double>(), 0.0);
    EXPECT_EQ(stats.at("lights").at("total"), 1);
}

TEST_F(Cli, DiffReportsMetrics) {
    std::string scene = write("tiny.pbrt", kTinyScene);
    ASSERT_EQ(run("render " + scene + " --spp 2 -q -o " + path("a.pfm")).code, 0);
    Result r = run("diff " + path("a.pfm") + " " + path("a.pfm") + " --json");
    EXPECT_EQ(r.code, 0) << r.output;
    nlohmann::json d = nlohmann::json::parse(r.output);
    EXPECT_EQ(d.at("relmse"), 0.0) << r.output;
    EXPECT_EQ(d.at("mean_a"), d.at("mean_b")) << r.output;
}

TEST_F(Cli, MissingSceneFile) { expect_input_error(path("nope.pbrt"), "nope.pbrt"); }

TEST_F(Cli, ZeroResolution) {
    expect_input_error(write("s.pbrt", R"(Film "rgb" "integer xresolution" [ 0 ]
WorldBegin
)"),
                       "s.pbrt:1:");
}

TEST_F(Cli, NegativeResolution) {
    expect_input_error(write("s.pbrt", R"(Film "rgb" "integer yresolution" [ -5 ]
WorldBegin
)"),
                       "s.pbrt:1:");
}

TEST_F(Cli, ResolutionTooLargeForMemory) {
    expect_input_error(
        write("s.pbrt",
              R"(Film "rgb" "integer xresolution" [ 60000 ] "integer yresolution" [ 60000 ]
WorldBegin
)"),
        "too large");
}

TEST_F(Cli, UnusedFilmParameter) {
    expect_input_error(write("s.pbrt", R"(Film "rgb" "float bogus" [ 1 ]
WorldBegin
)"),
                       "s.pbrt:1:");
}

TEST_F(Cli, UnknownIntegratorIsAUsageError) {
    Result r = run("render --integrator nope -q -o " + path("x.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_FALSE(fs::exists(path("x.png")));
}

TEST_F(Cli, UnknownSetKeyIsAUsageError) {
    std::string scene = write("tiny.pbrt", kTinyScene);
    Result r = run("render " + scene + " --set path.nope=1 -q -o " + path("x.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_FALSE(fs::exists(path("x.png")));
}

TEST_F(Cli, BadOutputExtensionIsAUsageError) {
    Result r = run("render -q -o " + path("x.txt"));
    EXPECT_EQ(r.code, 2) << r.output;
}

TEST_F(Cli, SetBeforeTheSceneLeavesTheScenePositional) {
    std::string scene = write("tiny.pbrt", kTinyScene);
    Result r = run("render --set path.maxdepth=2 " + scene +
                   " --set path.rrdepth=3 --spp 1 -q -o " + path("a.png"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(path("a.png")));
}

// Every bad option gets one line: the prefix, the option, what it expects and what it got.
TEST_F(Cli, NumericOptionsSayWhatTheyExpectAndGot) {
    struct Case {
        const char* args;
        const char* message;
    };
    for (const Case& c : {
             Case{"--spp abc", "manylight: --spp: expected a positive integer, got \"abc\""},
             Case{"--spp 0", "manylight: --spp: expected a positive integer, got \"0\""},
             Case{"--spp 99999999999", "--spp: expected a positive integer, got \"99999999999\""},
             Case{"--threads -2", "--threads: expected a positive integer, got \"-2\""},
             Case{"--max-depth x", "--max-depth: expected a non-negative integer, got \"x\""},
             Case{"--seed 1.5", "--seed: expected a non-negative integer, got \"1.5\""},
             Case{"--time-limit 0",
                  "--time-limit: expected a positive number of seconds, got \"0\""},
             Case{"--time-limit nan", "--time-limit: expected a positive number of seconds"},
             Case{"--resolution 64",
                  "--resolution: expected WIDTHxHEIGHT, e.g. 640x360, got \"64\""},
             Case{"--set vplcount=1", "--set: expected NAME.KEY=VALUE"},
             Case{"--sampler halton", "--sampler: unknown sampler \"halton\"; expected one of:"},
             Case{"--bias-check yes",
                  "--bias-check: unknown bias check mode \"yes\"; expected one of: auto, on, off"},
             Case{"--bias-check-share 0.9",
                  "--bias-check-share: expected a share of the time in (0, 0.5], e.g. 0.1, got "
                  "\"0.9\""},
             Case{"--bias-check-pixels 0",
                  "--bias-check-pixels: expected a positive integer, got \"0\""},
             Case{"--bias-check-pixels 1", "--bias-check-pixels: expected at least 2 pixels"},
             Case{"--bias-check-spp -1", "--bias-check-spp: expected a positive integer"},
         }) {
        Result r = run(std::string("render ") + c.args + " -q -o " + path("x.png"));
        EXPECT_EQ(r.code, 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << ": " << r.output;
        EXPECT_EQ(r.output.find("1797693"), std::string::npos) << r.output;  // no double range
        EXPECT_EQ(r.output.rfind("manylight: ", 0), 0u) << "one prefix: " << r.output;
        EXPECT_FALSE(fs::exists(path("x.png")));
    }
}

TEST_F(Cli, UnknownIntegratorListsTheValidNames) {
    Result r = run("render --integrator nosuch -q -o " + path("x.png"));
    EXPECT_EQ(r.code, 2) << r.output;
    for (const char* name : {"path", "bdpt", "vpl", "lightcuts", "mdlightcuts", "pssmlt"})
        EXPECT_NE(r.output.find(name), std::string::npos) << name << ": " << r.output;
    EXPECT_NE(r.output.find("unknown integrator \"nosuch\""), std::string::npos) << r.output;
}

// `--integrator manylight` is the recommended many-light integrator, under its own name and
// settings: the same image as naming it.
TEST_F(Cli, ManylightNamesTheRecommendedIntegrator) {
    std::string scene = write("tiny.pbrt", kTinyScene);
    const std::string common = " --spp 2 -q --set vpl.count=64 --set " +
                               std::string(ml::kRecommendedManyLight) + ".samples=2 ";
    Result a = run("render " + scene + " --integrator manylight" + common + "-o " + path("a.exr") +
                   " --stats " + path("s.json"));
    ASSERT_EQ(a.code, 0) << a.output;
    std::ifstream js(path("s.json"));
    EXPECT_EQ(nlohmann::json::parse(js).at("integrator"), ml::kRecommendedManyLight);
    Result b = run("render " + scene + " --integrator " + ml::kRecommendedManyLight + common +
                   "-o " + path("b.exr"));
    ASSERT_EQ(b.code, 0) << b.output;
    Result d = run("diff --json " + path("a.exr") + " " + path("b.exr"));
    ASSERT_EQ(d.code, 0) << d.output;
    EXPECT_EQ(nlohmann::json::parse(d.output.substr(d.output.find('{'))).at("rmse"), 0.0);
}

TEST_F(Cli, OutputInAMissingFolderNamesTheUsersPath) {
    std::string out = path("no/such/folder/x.png");
    Result r = run("render -q -o " + out);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(out), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find(".tmp"), std::string::npos) << r.output;
    r = run("render -q --spp 1 --resolution 8x8 -o " + path("x.png") + " --stats " +
            path("none/s.json"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(path("none/s.json")), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("x.png")));
}

// pbrt-v4's film scales by the exposure time (the camera's shutter interval) * iso / 100;
// spectral sensors and white balance are errors at their place, never silently ignored, and
// "exposuretime" is no film parameter of pbrt-v4's.
TEST_F(Cli, FilmExposureScalesAndSpectralSensorsAreErrors) {
    auto scene = [&](const std::string& name, const std::string& film,
                     const std::string& camera = "") {
        std::string text = kTinyScene;
        text.replace(text.find("Film \"rgb\""), 10, "Film \"rgb\" " + film);
        text.replace(text.find("Camera \"perspective\""), 20, "Camera \"perspective\" " + camera);
        return write(name, text);
    };
    auto mean = [&](const std::string& file) {
        Result r = run("render " + file + " --spp 4 --seed 3 -q -o " + path("m.pfm"));
        EXPECT_EQ(r.code, 0) << r.output;
        Result d = run("diff " + path("m.pfm") + " " + path("m.pfm") + " --json");
        return nlohmann::json::parse(d.output).at("mean_a").at(0).get<double>();
    };
    double plain = mean(scene("plain.pbrt", ""));
    double bright = mean(scene("bright.pbrt", "\"float iso\" [ 400 ]",
                               "\"float shutteropen\" [ 0.25 ] \"float shutterclose\" [ 0.75 ]"));
    ASSERT_GT(plain, 0);
    EXPECT_NEAR(bright / plain, 2.0, 1e-3);
    // A shutter of no length (which pbrt-v4 refuses) freezes time: an exposure of 1.
    double instant = mean(
        scene("instant.pbrt", "", "\"float shutteropen\" [ 0.5 ] \"float shutterclose\" [ 0.5 ]"));
    EXPECT_NEAR(instant / plain, 1.0, 1e-3);
    expect_input_error(scene("time.pbrt", "\"float exposuretime\" [ 0.5 ]"), "exposuretime");
    expect_input_error(scene("sensor.pbrt", "\"string sensor\" [ \"canon_eos_100d\" ]"),
                       "sensor.pbrt:3:");
    expect_input_error(scene("wb.pbrt", "\"float whitebalance\" [ 5000 ]"), "wb.pbrt:3:");
    expect_input_error(scene("iso.pbrt", "\"float iso\" [ 0 ]"), "must be positive");
}

TEST_F(Cli, StatsCountNonFiniteSamples) {
    std::string scene = write("tiny.pbrt", kTinyScene);
    Result r =
        run("render " + scene + " --spp 2 -q -o " + path("a.exr") + " --stats " + path("s.json"));
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream js(path("s.json"));
    nlohmann::json stats = nlohmann::json::parse(js);
    EXPECT_EQ(stats.at("film").at("nonfinite_samples"), 0) << stats;
}

// The bias check: on by default for a many-light integrator (its figures in --stats and a line
// after the summary), off for path unless asked for, and off when told.
TEST_F(Cli, BiasCheckInStatsAndSummary) {
    auto render = [&](const std::string& args) {
        Result r = run("render --resolution 16x16 --spp 2 -o " + path("b.png") + " --stats " +
                       path("b.json") + " " + args);
        EXPECT_EQ(r.code, 0) << args << ": " << r.output;
        std::ifstream js(path("b.json"));
        return std::pair{r.output, nlohmann::json::parse(js)};
    };
    auto [out, stats] = render("--integrator vpl --set vpl.count=1000");
    ASSERT_TRUE(stats.contains("bias_check")) << stats;
    const nlohmann::json& check = stats.at("bias_check");
    EXPECT_EQ(check.at("pixels"), 256) << check;
    EXPECT_EQ(check.at("ratio").size(), 3u) << check;
    EXPECT_EQ(check.at("ci95").size(), 3u) << check;
    EXPECT_TRUE(check.at("verdict") == "ok" || check.at("verdict") == "off") << check;
    EXPECT_NE(out.find("manylight: bias check: image / path r "), std::string::npos) << out;
    EXPECT_FALSE(render("--integrator path").second.contains("bias_check"));
    EXPECT_TRUE(render("--integrator path --bias-check on --bias-check-pixels 20")
                    .second.at("bias_check")
                    .at("pixels") == 20);
    EXPECT_FALSE(render("--integrator vpl --set vpl.count=1000 --bias-check off")
                     .second.contains("bias_check"));
}

// --time-limit is a contract even when one pass, or a Metropolis bootstrap, would take far
// longer: the loops stop starting work once the time is spent. Each setting below would run for
// minutes untimed; the render phase must end near the limit (generous slack for a loaded machine).
TEST_F(Cli, TimeLimitHoldsWhenOnePassWouldTakeMinutes) {
    const double limit = 0.5;
    for (const std::string& integrator :
         {std::string("lightcuts --set vpl.count=20000 --set lightcuts.error=1e-6 "
                      "--set lightcuts.max_cut=20000 --set lights.direct=points"),
          std::string("mdlightcuts --set vpl.count=20000 --set mdlightcuts.error=1e-6 "
                      "--set mdlightcuts.max_cut=20000 --set lights.direct=points"),
          std::string("pssmlt --set pssmlt.bootstrap=20000000"),
          std::string("mlt --set mlt.bootstrap=20000000")}) {
        Result r =
            run("render --resolution 64x64 --integrator " + integrator + " --time-limit " +
                std::to_string(limit) + " -o " + path("t.exr") + " --stats " + path("t.json"));
        ASSERT_EQ(r.code, 0) << integrator << ": " << r.output;
        std::ifstream js(path("t.json"));
        nlohmann::json stats = nlohmann::json::parse(js);
        double render = stats.at("seconds").at("render");
        EXPECT_LT(render, limit + 1.5) << integrator << ": " << stats;
    }
}

// Under a time limit that one pass of whole cuts would overrun many times, mdlightcuts,
// bdlightcuts and lightcuts stop their cuts at the cap a timing probe says fits
// (manylight/pilot.h), so the first pass ends in time and no pixel is left black; they say so in a
// warning and the stats.
TEST_F(Cli, CutIntegratorsFinishTheirFirstPassUnderATimeLimit) {
    for (auto [integrator, samples] :
         {std::pair{std::string("mdlightcuts"), 32}, std::pair{std::string("bdlightcuts"), 16}}) {
        Result r = run("render --resolution 32x32 --integrator " + integrator +
                       " --set vpl.count=20000 --set " + integrator + ".error=1e-6 --set " +
                       integrator + ".max_cut=20000 --set lights.direct=points --time-limit 4 -o " +
                       path("t.exr") + " --stats " + path("t.json"));
        ASSERT_EQ(r.code, 0) << integrator << ": " << r.output;
        std::ifstream js(path("t.json"));
        nlohmann::json stats = nlohmann::json::parse(js);
        EXPECT_GE(stats.at("spp").get<int>(), samples) << stats;
        EXPECT_EQ(stats.at("film").at("pixels_without_samples"), 0) << stats;
        const nlohmann::json& cap = stats.at(integrator).at("time_cap");
        EXPECT_LT(cap.at("cap").get<int>(), 20000) << cap;
        EXPECT_GT(cap.at("full_pass_seconds").get<double>(), 4.0) << cap;
        EXPECT_NE(r.output.find("to end a pass within --time-limit"), std::string::npos)
            << r.output;
    }
}

// A VPL sampler that cannot build its count within a time limit builds fewer (manylight/
// vpl_budget.h): the render phase still ends within the contract's 10% of the limit (plus a
// little for a loaded machine), says so in a warning and the stats, and the image is lit.
TEST_F(Cli, VplBuildFitsTheTimeLimit) {
    const double limit = 4;
    Result r =
        run("render --resolution 32x32 --integrator mdlightcuts --set vpl.sampler=bidirectional "
            "--set vpl.count=3000000 --time-limit 4 -o " +
            path("t.exr") + " --stats " + path("t.json"));
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream js(path("t.json"));
    nlohmann::json stats = nlohmann::json::parse(js);
    EXPECT_LT(stats.at("seconds").at("render").get<double>(), 1.1 * limit + 0.5) << stats;
    EXPECT_EQ(stats.at("film").at("pixels_without_samples"), 0) << stats;
    const nlohmann::json& md = stats.at("mdlightcuts");
    EXPECT_EQ(md.at("vpl_count_requested").get<int>(), 3000000) << md;
    EXPECT_LT(md.at("vpl_count_used").get<int>(), 3000000) << md;
    EXPECT_NE(r.output.find("vpl.count was reduced from 3000000 to"), std::string::npos)
        << r.output;
    ml::Image img = ml::read_image(path("t.exr"));
    double sum = 0;
    for (const ml::RGB& p : img.pixels) sum += p.luminance();
    EXPECT_GT(sum / double(img.pixels.size()), 0.01);
}

// `manylight view` and `render --look-at`: bad input is a clear error before anything listens.
TEST(CliView, BadInputIsAClearError) {
    Result r = run("view /nonexistent/scene.pbrt --port 0");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("/nonexistent/scene.pbrt"), std::string::npos) << r.output;
    r = run("view x.pbrt --port 70000");
    EXPECT_EQ(r.code, 2) << r.output;
    r = run("view x.pbrt --integrator vpl");
    EXPECT_EQ(r.code, 2) << r.output;
    r = run("render --look-at 0 0 0 0 0 1 0 1 -q -o /tmp/manylight-cli-never.png");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_FALSE(std::filesystem::exists("/tmp/manylight-cli-never.png"));
}
