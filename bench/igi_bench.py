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
Usage: bench/igi_bench.py [--reps N] [--bin PATH]
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
    "igi 4x4, 256 VPLs, no filter": ["igi.vpls=256", "igi.interleave=4x4", "igi.filter=0"],
    "1x1, 16 VPLs (equal time)": ["igi.vpls=16", "igi.interleave=1x1", "igi.filter=0"],
    "1x1, 256 VPLs (the same VPLs)": ["igi.vpls=256", "igi.interleave=1x1", "igi.filter=0"],
    "igi 4x4, 256 VPLs, filter 1, no packets": ["igi.vpls=256", "igi.interleave=4x4",
                                               "igi.filter=1", "igi.packets=false"],
}
REFERENCE = ["igi.vpls=1024", "igi.interleave=1x1", "igi.filter=0"]


def command(sets, out, stats):
    cmd = [BIN, "render", SCENE, "-q", "--integrator", "igi", "--resolution", "640x360",
           "--spp", "1", "--threads", "2", "-o", out, "--stats", stats]
    for s in sets:
        cmd += ["--set", s]
    return cmd


def render(sets, tmp, name):
    out, stats = os.path.join(tmp, name + ".exr"), os.path.join(tmp, name + ".json")
    subprocess.run(command(sets, out, stats), check=True)
    with open(stats) as f:
        return out, json.load(f)


def relmse(a, b):
    r = subprocess.run([BIN, "diff", a, b, "--json"], check=True, capture_output=True, text=True)
    return json.loads(r.stdout)["relmse"]


def main():
    global BIN
    if "--bin" in sys.argv:
        BIN = os.path.abspath(sys.argv[sys.argv.index("--bin") + 1])
    reps = int(sys.argv[sys.argv.index("--reps") + 1]) if "--reps" in sys.argv else 3
    with tempfile.TemporaryDirectory() as tmp:
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
        a, b = rows["igi 4x4, 256 VPLs, filter 1"], rows["1x1, 16 VPLs (equal time)"]
        print(f"\nequal time: relMSE ratio (4x4 filtered / 1x1 16 VPLs) = {a[1] / b[1]:.3f} at "
              f"time ratio {a[0] / b[0]:.2f}")
        p = rows["igi 4x4, 256 VPLs, filter 1, no packets"]
        print(f"packets of 8: time ratio (single rays / packets) = {p[0] / a[0]:.2f}")
        print("\ncommand (OUT, STATS: any paths): " + " ".join(
            os.path.relpath(c, ROOT) if c.startswith(ROOT) else c
            for c in command(CONFIGS["igi 4x4, 256 VPLs, filter 1"], "OUT.exr", "STATS.json")))


if __name__ == "__main__":
    main()
