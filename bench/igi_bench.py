#!/usr/bin/env python3
"""Issue 16: the igi integrator on the kitchen at 640x360, 2 threads (the viewer's moving frames).

Frames: `igi` at 1 spp with 256 VPLs, interleave 4x4, filter 1 (one 4x4 pattern), full visibility (every
VPL of a pixel's subset through a shadow ray); its render time is the viewer's time from a
camera move to the new frame (the viewer renders each frame through the same render_built_scene,
the scene already built), and 1 / time its frames per second.

Equal time: against the same count of VPLs per pixel gathered without interleaving (1x1, 16 VPLs,
no filter: the same shadow rays per pixel, so about the same time), and for scale the same 256
VPLs without interleaving (16x the shadow rays). relMSE against a VPL reference: 1x1 with 1024
VPLs. All at the same seed and 1 spp, so the camera rays and the sampled direct light are the
same in every image and the differences are the VPL gathering's alone.

Packets: the 4x4 frame with shadow rays one by one (igi.packets=false) against packets of 8.
Runs alternate between configurations (the machine is shared; ratios are in one run).

Viewer frames (session 9): the viewer's own moving frames through `manylight view
--bench-frames N` (no server: N views of an orbit, each rendered at the preview's 1/2 resolution,
the first frame after a move, and at full resolution, the frame once the view stops, alternating;
wall milliseconds and the process's CPU seconds per frame, render and tone mapping included).
With --baseline PATH (main's binary, which has no --bench-frames), the viewer's frame as
`render` runs it (1 spp, igi.filter_direct, lights.direct_samples=1) alternates between PATH and
--bin, its seconds.render compared in one run.
With --ab PATH[,PATH...] (session 12), only the full-resolution frames of `view --bench-frames`:
--reps runs of --frames frames each, alternating the PATHs and --bin (last); the median CPU
seconds per frame of each and its ratio to the first PATH's, from one run.
Usage: bench/igi_bench.py [--reps N] [--bin PATH] [--baseline PATH] [--frames N] [--only-frames]
       bench/igi_bench.py --ab PATH[,PATH...] [--reps N] [--frames N] [--bin PATH]
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "manylight")
SCENE = os.path.join(ROOT, "..", "shared", "scenes", "kitchen", "scene-v4.pbrt")

CONFIGS = {
    "igi 4x4, 256 VPLs, filter 1": ["igi.vpls=256", "igi.interleave=4x4", "igi.filter=1"],
    "igi 4x4, 256 VPLs, filter 2": ["igi.vpls=256", "igi.interleave=4x4", "igi.filter=2"],
    "igi 4x4, 256 VPLs, no filter": ["igi.vpls=256", "igi.interleave=4x4", "igi.filter=0"],
    "1x1, 16 VPLs (equal time)": ["igi.vpls=16", "igi.interleave=1x1", "igi.filter=0"],
    "1x1, 256 VPLs (the same VPLs)": ["igi.vpls=256", "igi.interleave=1x1", "igi.filter=0"],
    "igi 4x4, 256 VPLs, filter 1, no packets": ["igi.vpls=256", "igi.interleave=4x4",
                                               "igi.filter=1", "igi.packets=false"],
}
REFERENCE = ["igi.vpls=1024", "igi.interleave=1x1", "igi.filter=0"]
# The viewer's moving frame as `render` gives it (apps/view_renderer.cpp, options_for).
VIEWER_FRAME = ["igi.vpls=256", "igi.interleave=4x4", "igi.filter=1", "lights.direct_samples=1",
                "lights.direct_mis=glossy", "igi.filter_direct=true"]


def command(sets, out, stats, binary=None):
    cmd = [binary or BIN, "render", SCENE, "-q", "--integrator", "igi", "--resolution", "640x360",
           "--spp", "1", "--threads", "2", "-o", out, "--stats", stats]
    for s in sets:
        cmd += ["--set", s]
    return cmd


def render(sets, tmp, name, binary=None):
    out, stats = os.path.join(tmp, name + ".exr"), os.path.join(tmp, name + ".json")
    subprocess.run(command(sets, out, stats, binary), check=True)
    with open(stats) as f:
        return out, json.load(f)


def relmse(a, b):
    r = subprocess.run([BIN, "diff", a, b, "--json"], check=True, capture_output=True, text=True)
    return json.loads(r.stdout)["relmse"]


def arg(name, default=None):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def viewer_frames(frames):
    cmd = [BIN, "view", SCENE, "--resolution", "640x360", "--threads", "2", "--bench-frames",
           str(frames)]
    r = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    med = statistics.median
    print(f"\nviewer frames ({frames} views of an orbit, 2 degrees apart; median; CPU: the "
          "process's user + system seconds over both threads):")
    print("| frame | wall ms | frames/s (wall) | CPU s | wall ms if CPU / 2 (2 free cores) |")
    print("|---|---|---|---|---|")
    for name, key in ((f"preview (1/{r['preview']} resolution, first frame after a move)",
                       "preview"), ("full resolution (once the view stops)", "full")):
        ms, cpu = med(r[key + "_ms"]), med(r[key + "_cpu_s"])
        print(f"| {name} | {ms:.0f} | {1000 / ms:.1f} | {cpu:.3f} | {500 * cpu:.0f} |")
    print("command: " + " ".join(os.path.relpath(c, ROOT) if c.startswith(ROOT) else c
                                 for c in cmd))


def ab_full_frames(others, reps, frames):
    binaries = others + [BIN]
    cpu = {b: [] for b in binaries}
    ms = {b: [] for b in binaries}
    for rep in range(reps):
        for binary in binaries:
            # The default preview: binaries before session 12 listed no frame with --preview 1.
            cmd = [binary, "view", SCENE, "--resolution", "640x360", "--threads", "2",
                   "--bench-frames", str(frames)]
            r = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
            cpu[binary] += r["full_cpu_s"]
            ms[binary] += r["full_ms"]
    med = statistics.median
    first = med(cpu[binaries[0]])
    print(f"full-resolution frames, {reps} runs of {frames} alternating (median over "
          f"{len(cpu[BIN])} frames each; CPU: user + system seconds of both threads)")
    print("| binary | CPU s per frame | wall ms (this machine, now) | CPU / 2: ms on 2 free cores "
          "| ratio to the first (CPU s) |")
    print("|---|---|---|---|---|")
    for b in binaries:
        c = med(cpu[b])
        print(f"| {b} | {c:.3f} | {med(ms[b]):.0f} | {500 * c:.0f} | {c / first:.3f} |")


def baseline_frames(baseline, reps, tmp):
    times = {"baseline": [], "this": []}
    for rep in range(reps):
        for name, binary in (("baseline", baseline), ("this", BIN)):
            try:
                _, s = render(VIEWER_FRAME, tmp, "frame-" + name, binary)
            except subprocess.CalledProcessError:
                # Binaries before session 12 know no lights.direct_mis: their viewer's frame
                # took a light and a BSDF sample with MIS.
                sets = [x for x in VIEWER_FRAME if not x.startswith("lights.direct_mis")]
                _, s = render(sets, tmp, "frame-" + name, binary)
            times[name].append(s["seconds"]["render"])
    a, b = statistics.median(times["baseline"]), statistics.median(times["this"])
    print(f"\nthe viewer's frame through `render` (median of {reps}, alternating): baseline "
          f"{1000 * a:.0f} ms, this {1000 * b:.0f} ms, ratio this / baseline {b / a:.2f}")
    print("command: " + " ".join(os.path.relpath(c, ROOT) if c.startswith(ROOT) else c
                                 for c in command(VIEWER_FRAME, "OUT.exr", "STATS.json")))


def main():
    global BIN
    if "--bin" in sys.argv:
        BIN = os.path.abspath(arg("--bin"))
    reps = int(arg("--reps", 3))
    if "--ab" in sys.argv:
        ab_full_frames([os.path.abspath(b) for b in arg("--ab").split(",")], reps,
                       int(arg("--frames", 5)))
        return
    with tempfile.TemporaryDirectory() as tmp:
        if "--baseline" in sys.argv:
            baseline_frames(os.path.abspath(arg("--baseline")), reps, tmp)
        viewer_frames(int(arg("--frames", 5)))
        if "--only-frames" in sys.argv:
            return
        ref, ref_stats = render(REFERENCE, tmp, "reference")
        times = {k: [] for k in CONFIGS}
        images = {}
        for rep in range(reps):
            for i, (name, sets) in enumerate(CONFIGS.items()):
                out, s = render(sets, tmp, f"c{i}")
                times[name].append(s["seconds"]["render"])
                images[name] = out
        print(f"reference: igi 1x1, 1024 VPLs ({ref_stats['lights']['vpls']}), "
              f"{ref_stats['seconds']['render']:.1f} s")
        print("| configuration | render time (median of %d) | frames/s | relMSE vs reference |" % reps)
        print("|---|---|---|---|")
        rows = {}
        for name in CONFIGS:
            t = statistics.median(times[name])
            e = relmse(images[name], ref)
            rows[name] = (t, e)
            print(f"| {name} | {1000 * t:.0f} ms | {1 / t:.1f} | {e:.4f} |")
        b = rows["1x1, 16 VPLs (equal time)"]
        for f in ("filter 1", "filter 2"):
            a = rows["igi 4x4, 256 VPLs, " + f]
            print(f"\nequal time: relMSE ratio (4x4 {f} / 1x1 16 VPLs) = {a[1] / b[1]:.3f} at "
                  f"time ratio {a[0] / b[0]:.2f}")
        a = rows["igi 4x4, 256 VPLs, filter 1"]
        p = rows["igi 4x4, 256 VPLs, filter 1, no packets"]
        print(f"packets of 8: time ratio (single rays / packets) = {p[0] / a[0]:.2f}")
        print("\ncommand (OUT, STATS: any paths): " + " ".join(
            os.path.relpath(c, ROOT) if c.startswith(ROOT) else c
            for c in command(CONFIGS["igi 4x4, 256 VPLs, filter 1"], "OUT.exr", "STATS.json")))


if __name__ == "__main__":
    main()
