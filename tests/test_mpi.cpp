// Rendering across MPI ranks (issue 18): `mpirun -np 2 manylight render` against one process
// (this one), same seed. Bit-identical where every pixel is computed by one rank (pixel
// integrators, the many-light integrators: tiles); within float rounding where ranks' splats are
// summed (lighttracer, pssmlt: each rank's sums arrive as floats and are added in MPI's order). The
// work is split, not repeated: the rays of all ranks add up to one process's. An error on one
// rank ends the run with its message instead of a hang. Skipped, with the reason, without
// mpirun or in a build without MPI.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "distributed/mpi_world.h"
#include "film/image.h"
#include "integrators/render_job.h"
#include "scene/default_scene.h"
#include "scene/scene_desc.h"

namespace fs = std::filesystem;

namespace {

struct Result {
    int code = -1;
    std::string output;
    double seconds = 0;
};

Result shell(const std::string& cmd) {
    Result r;
    auto t0 = std::chrono::steady_clock::now();
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

// mpirun for 2 ranks on however many cores there are; as root (CI's containers) OpenMPI needs
// --allow-run-as-root. `timeout` turns a hang into a failure.
std::string mpirun(int ranks) {
    std::string cmd = "timeout 120 mpirun -np " + std::to_string(ranks) + " --oversubscribe";
    if (::geteuid() == 0) cmd += " --allow-run-as-root";
    return cmd + " ";
}

class Mpi : public ::testing::Test {
protected:
    void SetUp() override {
        if (!ml::mpi_built()) GTEST_SKIP() << "built without MPI (MANYLIGHT_MPI=OFF or no MPI)";
        if (shell("command -v mpirun").code != 0)
            GTEST_SKIP() << "mpirun is missing (apt-get install openmpi-bin; scripts/setup)";
        m_dir = fs::temp_directory_path() /
                ("manylight-mpi-" + std::to_string(::getpid()) + "-" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override {
        if (!m_dir.empty()) fs::remove_all(m_dir);
    }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    // The built-in Cornell box with `integrator` and `extra` options (--set ones), 40x30, seed
    // 7, one thread: rendered here in this process (render_scene, as the command line does), and
    // by `mpirun -np 2 manylight render` into a .pfm (float32, exact).
    struct Pair {
        ml::Image one, two;
        nlohmann::json stats_one, stats_two;
    };
    Pair render_both(const std::string& integrator, int spp,
                     const std::map<std::string, std::string>& set = {}) {
        Pair p;
        ml::RenderOptions o;
        o.integrator = integrator;
        o.width = 40, o.height = 30, o.spp = spp, o.seed = 7, o.threads = 1, o.set = set;
        ml::RenderOutput out = ml::render_scene(
            ml::parse_scene_string(ml::default_scene_text(), ".", "<cornell-box>"), o);
        p.one = out.image;
        p.stats_one = out.figures.to_json();
        std::string b = path(integrator + ".pfm"), args;
        for (const auto& [key, value] : set) args += " --set " + key + "=" + value;
        Result r = shell(mpirun(2) + MANYLIGHT_BINARY + " render -q --threads 1 --integrator " +
                         integrator + " --resolution 40x30 --seed 7 --spp " + std::to_string(spp) +
                         args + " -o " + b + " --stats " + b + ".json");
        EXPECT_EQ(r.code, 0) << r.output;
        if (r.code != 0) return p;
        p.two = ml::read_image(b);
        p.stats_two = nlohmann::json::parse(std::ifstream(b + ".json"));
        return p;
    }
    // The work was split, not repeated: with `exact`, as many rays in all as one process
    // shoots; else (every rank builds the same VPLs, light tree, pilot or Metropolis bootstrap)
    // fewer than twice as many. The figures say two ranks, each with its time.
    static void expect_split(const Pair& p, bool exact) {
        const auto& one = p.stats_one.at("rays");
        const auto& two = p.stats_two.at("rays");
        if (exact) {
            EXPECT_EQ(two.at("total"), one.at("total"));
            EXPECT_EQ(two.at("camera"), one.at("camera"));
        } else {
            EXPECT_LT(two.at("total").get<double>(), 2 * one.at("total").get<double>());
        }
        EXPECT_EQ(p.stats_two.at("spp"), p.stats_one.at("spp"));
        EXPECT_FALSE(p.stats_one.contains("mpi"));
        EXPECT_EQ(p.stats_two.at("mpi").at("ranks"), 2);
        EXPECT_EQ(p.stats_two.at("mpi").at("seconds_render_per_rank").size(), 2u);
    }
    static void expect_bit_identical(const Pair& p) {
        ASSERT_EQ(p.one.pixels.size(), p.two.pixels.size());
        size_t differ = 0, lit = 0;
        for (size_t i = 0; i < p.one.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                differ += p.one.pixels[i][c] != p.two.pixels[i][c];
                lit += p.one.pixels[i][c] > 0;
            }
        EXPECT_EQ(differ, 0u);
        EXPECT_GT(lit, p.one.pixels.size());  // not a black image on both sides
    }
    // Each channel within `rel` of one process's (relative, floor 1e-6 absolute).
    static void expect_within(const Pair& p, double rel) {
        ASSERT_EQ(p.one.pixels.size(), p.two.pixels.size());
        double worst = 0;
        size_t lit = 0;
        for (size_t i = 0; i < p.one.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                double a = p.one.pixels[i][c], b = p.two.pixels[i][c];
                worst = std::max(worst, std::abs(a - b) / std::max(std::abs(a), 1e-6));
                lit += a > 0;
            }
        EXPECT_LE(worst, rel);
        EXPECT_GT(lit, p.one.pixels.size());
    }
    fs::path m_dir;
};

}  // namespace

// A pixel integrator: every pixel by one rank, in the same order: the same bits.
TEST_F(Mpi, PathIsBitIdenticalOnTwoRanks) {
    Pair p = render_both("path", 4);
    expect_bit_identical(p);
    expect_split(p, true);
}

// Many-light integrators: every rank builds the same VPLs and light tree from the seed, then
// renders its tiles: the same bits. igi sums its ranks' pixels on rank 0 before its filter.
TEST_F(Mpi, ManyLightIntegratorsAreBitIdenticalOnTwoRanks) {
    for (const char* integrator : {"lightcuts", "igi"}) {
        SCOPED_TRACE(integrator);
        Pair p = render_both(integrator, 2, {{"vpl.count", "300"}});
        expect_bit_identical(p);
        expect_split(p, false);
        EXPECT_EQ(p.stats_two.at("lights").at("vpls"), p.stats_one.at("lights").at("vpls"));
    }
}

// bdlightcuts with adaptive sampling: the shares come from every rank's first pass, summed and
// broadcast, so each rank's later passes are one process's.
TEST_F(Mpi, AdaptiveBdLightcutsIsBitIdenticalOnTwoRanks) {
    Pair p = render_both("bdlightcuts", 8, {{"vpl.count", "300"}, {"bdlightcuts.samples", "2"}});
    expect_bit_identical(p);
    expect_split(p, false);
    EXPECT_GT(p.stats_one.at("bdlightcuts").at("max_sample_share").get<double>(), 1.2)
        << "the shares do not vary";
}

// Splat integrators: light paths split by the tiles that start them (lighttracer), Markov
// chains split between the ranks (pssmlt); the splats' sums of the ranks are added as floats
// on rank 0, in another order than one process's doubles: equal within float rounding.
TEST_F(Mpi, SplatIntegratorsAgreeWithinRoundingOnTwoRanks) {
    {
        Pair p = render_both("lighttracer", 4);
        expect_within(p, 1e-5);
        expect_split(p, true);
    }
    {
        Pair p = render_both("pssmlt", 4, {{"pssmlt.bootstrap", "5000"}});
        expect_within(p, 1e-5);
        expect_split(p, false);
        // The chains' mutations of both ranks add up to one process's.
        EXPECT_EQ(p.stats_two.at("pssmlt").at("mutations"),
                  p.stats_one.at("pssmlt").at("mutations"));
        EXPECT_EQ(p.stats_two.at("pssmlt").at("mutations"), 40 * 30 * 4);
    }
}

// A rank that fails ends the run: a non-zero exit, the failing rank's message, no image, and
// no hang (the other rank was waiting for it in the film's reduction).
TEST_F(Mpi, AFailingRankEndsTheRunWithItsMessage) {
    std::string out = path("fail.exr");
    Result r = shell("MANYLIGHT_TEST_FAIL_RANK=1 " + mpirun(2) + MANYLIGHT_BINARY +
                     " render -q --threads 1 --resolution 16x16 --spp 1 -o " + out);
    EXPECT_NE(r.code, 0) << r.output;
    EXPECT_NE(r.code, 124) << "mpirun hung: " << r.output;
    EXPECT_NE(r.output.find("manylight (rank 1 of 2): "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rank 1 fails on purpose"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

// --time-limit holds across ranks: the ranks run the same rounds and stop together, in time.
TEST_F(Mpi, TimeLimitHoldsAcrossRanks) {
    std::string out = path("timed.exr");
    Result r = shell(mpirun(2) + MANYLIGHT_BINARY +
                     " render -q --threads 1 --integrator path --resolution 32x32 --time-limit 1.5"
                     " -o " +
                     out + " --stats " + out + ".json");
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json stats = nlohmann::json::parse(std::ifstream(out + ".json"));
    EXPECT_GT(stats.at("spp").get<int>(), 0);
    for (double s : stats.at("mpi").at("seconds_render_per_rank")) EXPECT_LE(s, 1.5 + 0.5);
}

// A VPL build reduced by the time limit (manylight/vpl_budget.h): each rank times its own
// probes and the ranks take the least count (one all_min each, paired: no hang), so every rank
// shades with the same set; the render phase holds the limit on each.
TEST_F(Mpi, ReducedVplCountIsAgreedAcrossRanks) {
    const double limit = 4;
    std::string out = path("vpls.exr");
    Result r = shell(mpirun(2) + MANYLIGHT_BINARY +
                     " render -q --threads 1 --integrator mdlightcuts --resolution 32x32"
                     " --set vpl.sampler=bidirectional --set vpl.count=3000000 --time-limit 4"
                     " -o " +
                     out + " --stats " + out + ".json");
    ASSERT_EQ(r.code, 0) << r.output;
    nlohmann::json stats = nlohmann::json::parse(std::ifstream(out + ".json"));
    EXPECT_LT(stats.at("mdlightcuts").at("vpl_count_used").get<int>(), 3000000) << stats;
    EXPECT_EQ(stats.at("film").at("pixels_without_samples"), 0) << stats;
    for (double s : stats.at("mpi").at("seconds_render_per_rank"))
        EXPECT_LE(s, 1.1 * limit + 0.5) << stats;
}
