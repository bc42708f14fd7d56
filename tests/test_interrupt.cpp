// Ctrl-C keeps the work: `manylight render` run as a child process and sent SIGINT part way
// writes the image so far, each pixel the mean of the samples it got, says so on stderr and
// exits 130; with --checkpoint the render then resumes to the uninterrupted image, bit for bit.
// A second signal ends the process at once. Under mpirun, each rank saves and resumes its own
// part (rank r > 0 in FILE.rank<r>), and a checkpoint of two ranks is refused by one.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "distributed/mpi_world.h"
#include "film/image.h"
#include "render_helpers.h"
#include "temp_dir_test.h"

namespace fs = std::filesystem;

namespace {

struct Child {
    int code = -1;  // the exit code (128 + the signal where one ended it)
    std::string err;
    double seconds = 0;
    double stop_seconds = -1;  // from the first signal to the end (-1: none was sent)
};

// CPU seconds the process has used, all its threads together (/proc/PID/stat); -1 if unknown.
double cpu_seconds(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    size_t close = text.rfind(')');
    if (close == std::string::npos) return -1;
    std::istringstream fields(text.substr(close + 2));
    std::string field;
    double ticks = 0;
    // After the name: state (3) ... utime (14) and stime (15).
    for (int k = 3; k <= 15 && fields >> field; ++k)
        if (k >= 14) ticks += std::stod(field);
    return ticks / double(::sysconf(_SC_CLK_TCK));
}

// Runs the program with `args`, sends `signals` and waits for it (at most a minute: then it is
// killed and the test fails). The first signal goes once the program has used that many CPU
// seconds and, where `ready_file` is given, once that file exists (a checkpoint saved after the
// first pass): it is then rendering, however slowly a loaded machine or a sanitizer build started
// it (a signal during the load stops the program before any image). Each later one goes that many
// wall seconds after the one before.
Child run_and_signal(const std::vector<std::string>& args,
                     const std::vector<std::pair<double, int>>& signals, const fs::path& err_file,
                     const std::string& ready_file = "") {
    auto t0 = std::chrono::steady_clock::now();
    pid_t pid = fork();
    if (pid == 0) {
        int fd = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, 2);
        std::vector<char*> argv{const_cast<char*>(MANYLIGHT_BINARY)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(MANYLIGHT_BINARY, argv.data());
        ::_exit(127);
    }
    auto since = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    Child c;
    int status = 0;
    size_t next = 0;
    double last_signal = 0, first_signal = -1;
    while (true) {
        pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid) break;
        const bool due =
            next < signals.size() && (next == 0 ? cpu_seconds(pid) >= signals[0].first &&
                                                      (ready_file.empty() || fs::exists(ready_file))
                                                : since() - last_signal >= signals[next].first);
        if (due) {
            ::kill(pid, signals[next++].second);
            last_signal = since();
            if (next == 1) first_signal = last_signal;
        }
        if (since() > 60) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            ADD_FAILURE() << "the render did not end";
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    c.seconds = since();
    c.stop_seconds = first_signal >= 0 ? c.seconds - first_signal : -1;
    c.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::ifstream in(err_file);
    std::stringstream ss;
    ss << in.rdbuf();
    c.err = ss.str();
    return c;
}

class Interrupt : public ml::test::TempDirTest {
protected:
    Interrupt() : TempDirTest("interrupt") {}
};

}  // namespace

// Inside a sphere that emits 0.5 and reflects nothing, every sample is 0.5: a pixel of the
// partial image is 0.5 exactly where it got samples, however many, and 0 where it got none.
// Dividing by the samples asked for instead would show as values below 0.5.
TEST_F(Interrupt, CtrlCWritesThePartialImageAndExits130) {
    const std::string scene = path("glow.pbrt"), out = path("glow.pfm");
    std::ofstream(scene) << ml::test::furnace_scene(0.f, 0.5f, 16);
    Child c = run_and_signal(
        {"render", scene, "-q", "--threads", "1", "--integrator", "path", "--spp", "1000000",
         "--checkpoint", path("glow.ckpt"), "--checkpoint-every", "0", "-o", out},
        {{0.2, SIGINT}}, path("err.txt"), path("glow.ckpt"));
    EXPECT_EQ(c.code, 130) << c.err;
    EXPECT_NE(c.err.find("interrupted: wrote the image so far to " + out), std::string::npos)
        << c.err;
    EXPECT_NE(c.err.find("--resume " + path("glow.ckpt")), std::string::npos) << c.err;
    EXPECT_LT(c.seconds, 30);
    ASSERT_TRUE(fs::exists(out));
    ml::Image img = ml::read_image(out);
    size_t lit = 0, other = 0;
    for (const ml::RGB& p : img.pixels)
        for (int k = 0; k < 3; ++k) {
            lit += p[k] == 0.5f;
            other += p[k] != 0.5f && p[k] != 0.f;
        }
    EXPECT_EQ(other, 0u);
    EXPECT_GT(lit, 0u);
    EXPECT_TRUE(fs::exists(path("glow.ckpt")));
}

// Stopped by SIGINT with a checkpoint, then resumed from it: the uninterrupted image, bit for
// bit (.pfm holds the floats exactly).
TEST_F(Interrupt, AStoppedRenderResumesToTheSameImage) {
    const std::vector<std::string> common{"render",       "-q",   "--threads",    "1",
                                          "--integrator", "path", "--resolution", "16x12",
                                          "--spp",        "3000", "--seed",       "3"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = common;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    const std::string ckpt = path("box.ckpt");
    Child stopped = run_and_signal(
        with({"--checkpoint", ckpt, "--checkpoint-every", "0", "-o", path("part.pfm")}),
        {{0.2, SIGINT}}, path("err1.txt"), ckpt);
    ASSERT_EQ(stopped.code, 130) << stopped.err << " (the render ended before the signal?)";
    Child resumed = run_and_signal(
        with({"--resume", ckpt, "-o", path("resumed.pfm"), "--stats", path("resumed.json")}), {},
        path("err2.txt"));
    ASSERT_EQ(resumed.code, 0) << resumed.err;
    Child full = run_and_signal(with({"-o", path("full.pfm")}), {}, path("err3.txt"));
    ASSERT_EQ(full.code, 0) << full.err;
    nlohmann::json stats = nlohmann::json::parse(std::ifstream(path("resumed.json")));
    EXPECT_GT(stats.at("checkpoint").at("resumed_from").get<int>(), -1);
    ml::Image a = ml::read_image(path("full.pfm")), b = ml::read_image(path("resumed.pfm"));
    EXPECT_EQ(ml::test::differing_channels(a, b), 0u);
    EXPECT_GT(ml::test::lit_channels(a), 0u);
}

// Without a checkpoint and with a budget of a million samples per pixel, a pixel integrator
// (path) and a splat integrator (lighttracer) stop within moments of the signal, and every pixel
// of the partial image has samples: the rounds grow to 64 samples per pixel, not to the whole
// budget, so no round keeps the stop waiting and no part of the frame is left black.
TEST_F(Interrupt, AStopKeepsTheWholeFrameWithoutACheckpoint) {
    const std::string scene = path("glow.pbrt");
    std::ofstream(scene) << ml::test::furnace_scene(0.f, 0.5f, 16);
    for (const char* integrator : {"path", "lighttracer"}) {
        const std::string out = path(std::string(integrator) + ".pfm");
        Child c =
            run_and_signal({"render", scene, "-q", "--threads", "2", "--integrator", integrator,
                            "--spp", "1000000", "--resolution", "32x24", "-o", out},
                           {{3.0, SIGINT}}, path("err.txt"));
        EXPECT_EQ(c.code, 130) << integrator << ": " << c.err;
        EXPECT_LT(c.stop_seconds, 5) << integrator << ": the stop waited for a long round";
        ASSERT_TRUE(fs::exists(out)) << integrator;
        ml::Image img = ml::read_image(out);
        double sum = 0;
        size_t dark = 0;
        for (const ml::RGB& p : img.pixels) {
            dark += p[1] == 0.f;
            sum += p[1];
        }
        EXPECT_EQ(dark, 0u) << integrator << ": pixels without samples";
        // Each sample of path is 0.5; the light tracer's splats average 0.5 over the frame.
        EXPECT_NEAR(sum / double(img.pixels.size()), 0.5, 0.05) << integrator;
    }
}

// The second signal does not wait for the tile: the process ends at once, with 130.
TEST_F(Interrupt, ASecondSignalExitsAtOnce) {
    Child c = run_and_signal({"render", "-q", "--threads", "1", "--integrator", "path", "--spp",
                              "100000", "--resolution", "64x64", "-o", path("x.pfm")},
                             {{3.0, SIGTERM}, {0.02, SIGTERM}}, path("err.txt"));
    EXPECT_EQ(c.code, 130) << c.err;
    EXPECT_LT(c.stop_seconds, 5);
}

// Under mpirun: a time limit stops the two ranks part way, each saves its own part; resumed
// on two ranks without the limit, the image is one process's uninterrupted one, bit for bit.
// One process cannot resume the two ranks' checkpoint.
TEST_F(Interrupt, MpiRanksSaveAndResumeTheirParts) {
    if (!ml::mpi_built()) GTEST_SKIP() << "built without MPI (MANYLIGHT_MPI=OFF or no MPI)";
    if (std::system("command -v mpirun > /dev/null") != 0)
        GTEST_SKIP() << "mpirun is missing (apt-get install openmpi-bin; scripts/setup)";
    std::string mpirun = "timeout 120 mpirun -np 2 --oversubscribe";
    if (::geteuid() == 0) mpirun += " --allow-run-as-root";
    const std::string common = std::string(MANYLIGHT_BINARY) +
                               " render -q --threads 1 --integrator path --resolution 24x16 "
                               "--seed 5 --spp 3000 ";
    const std::string ckpt = path("mpi.ckpt");
    auto sh = [&](const std::string& cmd) {
        return std::system((cmd + " > " + path("log.txt") + " 2>&1").c_str());
    };
    ASSERT_EQ(sh(mpirun + " " + common + "--time-limit 0.1 --checkpoint " + ckpt + " -o " +
                 path("part.pfm") + " --stats " + path("part.json")),
              0);
    EXPECT_TRUE(fs::exists(ckpt));
    EXPECT_TRUE(fs::exists(ckpt + ".rank1"));
    nlohmann::json part = nlohmann::json::parse(std::ifstream(path("part.json")));
    ASSERT_LT(part.at("spp").get<int>(), 3000) << "the time limit did not stop the render";
    ASSERT_EQ(sh(mpirun + " " + common + "--resume " + ckpt + " -o " + path("resumed.pfm")), 0);
    ASSERT_EQ(sh(common + "-o " + path("full.pfm")), 0);
    ml::Image a = ml::read_image(path("full.pfm")), b = ml::read_image(path("resumed.pfm"));
    EXPECT_EQ(ml::test::differing_channels(a, b), 0u);
    EXPECT_GT(ml::test::lit_channels(a), 0u);
    // One process: refused, saying why.
    EXPECT_NE(sh(common + "--resume " + ckpt + " -o " + path("one.pfm")), 0);
    std::ifstream log(path("log.txt"));
    std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("ranks is 2 there, 1 here"), std::string::npos) << text;
}
