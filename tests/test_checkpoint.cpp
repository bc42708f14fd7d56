// Checkpoint and resume (--checkpoint, --resume): a render stopped part way (here by its own
// progress callback setting the cancel flag, as Ctrl-C does) and resumed from its checkpoint
// gives the uninterrupted render's image: bit for bit for pixel integrators (the many-light ones
// with a VPL set per pass included, and mdlightcuts' and bdlightcuts' passes), within float
// rounding for splats (lighttracer) and Markov chains (pssmlt, whose chains' states are saved),
// where only the order of the splat sums differs. A checkpoint of another scene, integrator,
// settings or version is refused; an integrator that cannot save its state is refused up front.
#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "integrators/render_job.h"
#include "render/checkpoint.h"
#include "render_helpers.h"
#include "scene/default_scene.h"
#include "scene/scene_desc.h"
#include "temp_dir_test.h"

namespace fs = std::filesystem;

namespace {

class Checkpoints : public ml::test::TempDirTest {
protected:
    Checkpoints() : TempDirTest("checkpoint") {}

    // The Cornell box at 24x18, seed 7, two threads.
    static ml::RenderOptions options(const std::string& integrator, int spp) {
        ml::RenderOptions o;
        o.integrator = integrator;
        o.width = 24, o.height = 18, o.spp = spp, o.seed = 7, o.threads = 2;
        o.scene_id = "cornell";
        return o;
    }
    static ml::RenderOutput render(const ml::RenderOptions& o) {
        return ml::render_scene(
            ml::parse_scene_string(ml::default_scene_text(), ".", "<cornell-box>"), o);
    }
    // Renders with a checkpoint and stops once `stop_at` of the work is done (the cancel flag,
    // as Ctrl-C sets it); returns the samples per pixel done in full.
    int render_stopped(ml::RenderOptions o, double stop_at, const std::string& file,
                       const std::string& resume = "") {
        std::atomic<bool> cancel{false};
        o.cancel = &cancel;
        o.on_progress = [&](double f) {
            if (f >= stop_at) cancel = true;
        };
        o.checkpoint = file;
        o.checkpoint_every = 1e9;  // only the save at the stop
        o.resume = resume;
        ml::RenderOutput out = render(o);
        EXPECT_TRUE(cancel.load()) << "the render was not stopped";
        EXPECT_TRUE(fs::exists(file));
        EXPECT_EQ(out.figures.checkpoint_saves, 1);
        return out.figures.spp;
    }
    // Stops the render at `stop_at`, resumes it to the end, and returns both images: the
    // uninterrupted one and the resumed one. `unit`: the samples per pixel of the loop's unit.
    std::pair<ml::Image, ml::Image> stop_and_resume(const ml::RenderOptions& o, double stop_at,
                                                    int unit = 1) {
        const std::string file = path("state.ckpt");
        const int done = render_stopped(o, stop_at, file);
        EXPECT_LT(done, *o.spp) << "stopped after the end: nothing is resumed";
        ml::RenderOptions r = o;
        r.resume = file;
        ml::RenderOutput resumed = render(r);
        // (The units are samples per pixel, passes of `unit` samples, or pssmlt's mutations.)
        EXPECT_GE(int64_t(resumed.figures.resumed_from) * unit, done);
        EXPECT_EQ(resumed.figures.spp, *o.spp);
        return {render(o).image, resumed.image};
    }
    static void expect_bit_identical(const ml::Image& a, const ml::Image& b) {
        EXPECT_EQ(ml::test::differing_channels(a, b), 0u);
        EXPECT_GT(ml::test::lit_channels(a), a.pixels.size());  // not black on both sides
    }
    // Each channel within `rel` (relative, floor 1e-6 absolute): float rounding.
    static void expect_within(const ml::Image& a, const ml::Image& b, double rel) {
        EXPECT_LE(ml::test::worst_relative_difference(a, b), rel);
        EXPECT_GT(ml::test::lit_channels(a), a.pixels.size());
    }
};

}  // namespace

// The path tracer, stopped twice (mid-round: some pixels a sample ahead) and resumed twice.
TEST_F(Checkpoints, PathResumesBitForBit) {
    ml::RenderOptions o = options("path", 16);
    const std::string a = path("a.ckpt"), b = path("b.ckpt");
    const int first = render_stopped(o, 0.3, a);
    const int second = render_stopped(o, 0.7, b, a);
    EXPECT_LT(first, 16);
    EXPECT_LE(first, second);
    EXPECT_LT(second, 16);
    ml::RenderOptions r = o;
    r.resume = b;
    expect_bit_identical(render(o).image, render(r).image);
}

// A many-light integrator with a new VPL set and light tree every pass (vpl.sets=pass, passes
// of 8 samples): the resumed render rebuilds the pass's set from the seed and the pass.
TEST_F(Checkpoints, LightcutsWithASetPerPassResumesBitForBit) {
    ml::RenderOptions o = options("lightcuts", 24);
    o.set = {{"vpl.count", "200"}, {"vpl.sets", "pass"}};
    auto [full, resumed] = stop_and_resume(o, 0.5);
    expect_bit_identical(full, resumed);
}

// mdlightcuts with its defaults: passes of 32 samples per pixel, each shaded by one product cut
// and with a VPL set of its own (vpl.sets=pass). Stopped in the second of four passes (some
// pixels a pass ahead) and resumed with another thread count; the pass's set is rebuilt from the
// seed and the pass. A checkpoint of other settings is refused.
TEST_F(Checkpoints, MdlightcutsResumesBitForBit) {
    ml::RenderOptions o = options("mdlightcuts", 4 * 32);
    o.set = {{"vpl.count", "200"}};
    const std::string file = path("md.ckpt");
    const int done = render_stopped(o, 0.4, file);
    EXPECT_LT(done, 4 * 32);
    ml::RenderOptions r = o;
    r.resume = file;
    r.threads = 1;
    ml::RenderOutput resumed = render(r);
    EXPECT_GE(resumed.figures.resumed_from * 32, done);
    EXPECT_EQ(resumed.figures.spp, 4 * 32);
    expect_bit_identical(render(o).image, resumed.image);
    r.set["mdlightcuts.samples"] = "16";
    EXPECT_THROW(render(r), ml::UsageError);
}

// bdlightcuts with its defaults: passes of 16 samples, adaptive sampling after the first (each
// pixel's share of the later passes from its neighbours' noise in the first). Stopped twice, in
// the first pass (the pixels that finished it keep their noise in the checkpoint) and in a later
// one, and resumed twice: the shares are planned again from the saved noise, exactly.
TEST_F(Checkpoints, BdlightcutsResumesBitForBit) {
    ml::RenderOptions o = options("bdlightcuts", 4 * 16);
    o.set = {{"vpl.count", "200"}};
    const std::string a = path("a.ckpt"), b = path("b.ckpt");
    const int first = render_stopped(o, 0.1, a);
    EXPECT_EQ(first, 0);  // in the first pass
    const int second = render_stopped(o, 0.6, b, a);
    EXPECT_GT(second, 0);
    EXPECT_LT(second, 4 * 16);
    ml::RenderOptions r = o;
    r.resume = b;
    ml::RenderOutput resumed = render(r);
    EXPECT_EQ(resumed.figures.spp, 4 * 16);
    const ml::RenderOutput full = render(o);
    EXPECT_GT(full.figures.integrator_stats.at("bdlightcuts").at("max_sample_share").get<double>(),
              1.0);
    expect_bit_identical(full.image, resumed.image);
}

// Light tracing: the splat sums are saved exactly; only their order of summation differs.
TEST_F(Checkpoints, LighttracerResumesWithinRounding) {
    auto [full, resumed] = stop_and_resume(options("lighttracer", 8), 0.4);
    expect_within(full, resumed, 1e-5);
}

// Metropolis: the chains' states (samplers, current paths, random numbers) are saved; the
// resumed chains go on as the uninterrupted ones do.
TEST_F(Checkpoints, PssmltResumesWithinRounding) {
    ml::RenderOptions o = options("pssmlt", 8);
    o.set = {{"pssmlt.bootstrap", "5000"}, {"pssmlt.chains", "64"}};
    auto [full, resumed] = stop_and_resume(o, 0.4);
    expect_within(full, resumed, 1e-5);
}

// Under a time limit the limit is the total over the runs: a render resumed with the same limit
// has none of it left and adds nothing; with a longer one it goes on.
TEST_F(Checkpoints, TheTimeLimitIsTheTotal) {
    ml::RenderOptions o = options("path", 1 << 20);
    o.time_limit = 0.3;
    o.checkpoint = path("t.ckpt");
    const int first = render(o).figures.spp;
    ASSERT_LT(first, 1 << 20);
    ml::RenderOptions again = o;
    again.resume = o.checkpoint;
    again.checkpoint = path("t2.ckpt");
    // The first run stopped where its next round was not expected to fit: the second has only
    // that rest of the limit.
    ml::RenderOutput same = render(again);
    EXPECT_GE(same.figures.spp, first);
    EXPECT_LT(same.figures.seconds_render, 0.5 * o.time_limit);
    ml::RenderOptions longer = again;
    longer.time_limit = 1.0;
    EXPECT_GT(render(longer).figures.spp, first);
}

// bdlightcuts (the default many-light integrator) under a time limit: the limit is the total,
// and the resumed render keeps the first run's pass plan (its cut cap, samples per pass and the
// passes each VPL set serves).
TEST_F(Checkpoints, BdlightcutsTakesTheTimeLimitAsTheTotal) {
    ml::RenderOptions o = options("bdlightcuts", 1 << 16);
    o.set = {{"vpl.count", "200"}};
    o.time_limit = 0.4;
    o.checkpoint = path("t.ckpt");
    const ml::RenderOutput first = render(o);
    ASSERT_GT(first.figures.spp, 0);
    ASSERT_LT(first.figures.spp, 1 << 16);
    ml::RenderOptions again = o;
    again.resume = o.checkpoint;
    again.checkpoint = path("t2.ckpt");
    const ml::RenderOutput same = render(again);
    EXPECT_GE(same.figures.spp, first.figures.spp);
    EXPECT_LT(same.figures.seconds_render, 0.5 * o.time_limit);
    ml::RenderOptions longer = again;
    longer.time_limit = 1.2;
    const ml::RenderOutput more = render(longer);
    EXPECT_GT(more.figures.spp, first.figures.spp);
    const auto& a = first.figures.integrator_stats.at("bdlightcuts");
    const auto& b = more.figures.integrator_stats.at("bdlightcuts");
    EXPECT_EQ(a.at("time_cap"), b.at("time_cap"));
    EXPECT_EQ(a.at("pass_samples"), b.at("pass_samples"));
    EXPECT_EQ(a.at("set_period"), b.at("set_period"));
}

// Periodic saves: with --checkpoint-every 0 one after every round, and the last is the end.
TEST_F(Checkpoints, SavesAfterEveryRoundWhenAsked) {
    ml::RenderOptions o = options("path", 4);
    o.checkpoint = path("every.ckpt");
    o.checkpoint_every = 0;
    ml::RenderOutput out = render(o);
    EXPECT_EQ(out.figures.checkpoint_saves, 4 + 1);  // a round per sample, and the end
    // Resuming a finished render renders nothing more and gives the same image.
    ml::RenderOptions r = options("path", 4);
    r.resume = o.checkpoint;
    expect_bit_identical(out.image, render(r).image);
}

// Another scene, integrator, setting, spp or version: refused, saying what differs.
TEST_F(Checkpoints, ACheckpointOfAnotherRenderIsRefused) {
    ml::RenderOptions o = options("path", 2);
    o.checkpoint = path("p.ckpt");
    render(o);
    auto refused = [&](ml::RenderOptions r, const std::string& what) {
        r.checkpoint.clear();
        r.resume = o.checkpoint;
        try {
            render(r);
            ADD_FAILURE() << "resumed another render (" << what << ")";
        } catch (const ml::UsageError& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("another render"), std::string::npos) << e.what();
        }
    };
    ml::RenderOptions r = o;
    r.integrator = "direct";
    refused(r, "integrator is path there, direct here");
    r = o;
    r.scene_id = "another";
    refused(r, "scene is cornell there, another here");
    r = o;
    r.set = {{"path.maxdepth", "3"}};
    refused(r, "settings");
    r = o;
    r.spp = 3;
    refused(r, "spp is 2 there, 3 here");
    r = o;
    r.seed = 8;
    refused(r, "seed");
    r = o;
    r.width = 25;
    refused(r, "resolution");

    // Another version: the file's fingerprint edited.
    std::ifstream in(o.checkpoint, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    nlohmann::json j = nlohmann::json::from_cbor(bytes);
    j["fingerprint"]["version"] = "manylight 0.0 checkpoint 0";
    std::vector<uint8_t> edited = nlohmann::json::to_cbor(j);
    std::ofstream(o.checkpoint, std::ios::binary)
        .write(reinterpret_cast<const char*>(edited.data()), std::streamsize(edited.size()));
    refused(o, "version is manylight 0.0 checkpoint 0 there");

    // Not a checkpoint at all.
    std::ofstream(o.checkpoint) << "hello";
    r = o;
    r.resume = o.checkpoint;
    r.checkpoint.clear();
    EXPECT_THROW(render(r), ml::UsageError);
}

TEST_F(Checkpoints, AnIntegratorThatCannotSaveItsStateIsRefused) {
    ml::RenderOptions o = options("mlt", 2);
    o.checkpoint = path("m.ckpt");
    try {
        render(o);
        ADD_FAILURE() << "mlt took a checkpoint";
    } catch (const ml::UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot save its state"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("pssmlt"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bdlightcuts"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(o.checkpoint));
    // A guided path tracer's state is its guide, which a checkpoint does not hold.
    ml::RenderOptions g = options("path", 2);
    g.set["path.guiding"] = "on";
    g.checkpoint = path("g.ckpt");
    EXPECT_THROW(render(g), ml::UsageError);
    EXPECT_FALSE(fs::exists(g.checkpoint));
    // So is bdlightcuts' with guided remainders.
    ml::RenderOptions b = options("bdlightcuts", 2);
    b.set["bdlightcuts.guiding"] = "on";
    b.checkpoint = path("b.ckpt");
    EXPECT_THROW(render(b), ml::UsageError);
    EXPECT_FALSE(fs::exists(b.checkpoint));
}
