#!/usr/bin/env python3
"""Scene benchmarks of the renderer foundation (issue: renderer foundation).

Runs manylight on the shared scenes at the settings pbrt-v4 and Tungsten were timed with on
this machine kind (2 threads), prints a table, and appends it with the command to
bench/history/log.md (the dated log; bench/RESULTS.md keeps the current figures). Usage: bench/scene_bench.py [--quick] [--no-append]
"""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "manylight")
SHARED = os.path.join(ROOT, "..", "shared")

# Times measured with pbrt-v4 and Tungsten on this machine kind (2 threads), from the issue.
PEERS = {
    "cornell": {"pbrt-v4": 35.6, "Tungsten": 19.2},
    "kitchen": {"pbrt-v4": 20.4},
}


def render(scene, args, tmp, name):
    out = os.path.join(tmp, name + ".exr")
    stats = os.path.join(tmp, name + ".json")
    cmd = [BIN, "render", scene, "-q", "--threads", "2", "-o", out, "--stats", stats] + args
    t0 = time.time()
    subprocess.run(cmd, check=True)
    wall = time.time() - t0
    with open(stats) as f:
        s = json.load(f)
    s["wall"] = wall
    s["cmd"] = " ".join(os.path.relpath(c, ROOT) if c.startswith(ROOT) else c for c in cmd)
    s["cmd"] = s["cmd"].replace(tmp, "OUT")
    return out, s


def diff(a, b):
    r = subprocess.run([BIN, "diff", a, b, "--json"], check=True, capture_output=True, text=True)
    return json.loads(r.stdout)


def main():
    quick = "--quick" in sys.argv
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        cornell = os.path.join(SHARED, "scenes/cornell-box/scene-v4.pbrt")
        kitchen = os.path.join(SHARED, "scenes/kitchen/scene-v4.pbrt")
        spp = "8" if quick else "64"
        _, s = render(cornell, ["--integrator", "path", "--resolution", "512x512", "--spp", spp,
                                "--max-depth", "64", "--seed", "1"], tmp, "cornell")
        rows.append((f"cornell-box 512x512 {spp}spp depth 64", s, PEERS["cornell"] if not quick else {}))
        kspp = "2" if quick else "16"
        _, s = render(kitchen, ["--integrator", "path", "--resolution", "640x360", "--spp", kspp,
                                "--max-depth", "17", "--seed", "1"], tmp, "kitchen")
        rows.append((f"kitchen 640x360 {kspp}spp depth 17", s, PEERS["kitchen"] if not quick else {}))
        # Accuracy: Cornell box at 256x256, 512 spp against both references.
        rspp = "32" if quick else "512"
        img, s = render(cornell, ["--integrator", "path", "--resolution", "256x256", "--spp", rspp,
                                  "--max-depth", "16", "--seed", "1"], tmp, "cornell256")
        ref_pbrt = os.path.join(SHARED, "references/cornell-box-path-256-2048spp.exr")
        d_pbrt = diff(img, ref_pbrt)

    lines = []
    lines.append("| run | load s | build s | render s | process wall s | Mrays/s | peak MB | peers (s) | ours / peer (wall) |")
    lines.append("|---|---|---|---|---|---|---|---|---|")
    for label, s, peers in rows:
        sec = s["seconds"]
        total = s["wall"]
        ratio = ", ".join(f"{k} {total / v:.2f}x" for k, v in peers.items())
        peer_s = ", ".join(f"{k} {v}" for k, v in peers.items())
        lines.append(f"| {label} | {sec['load']:.2f} | {sec['build']:.2f} | {sec['render']:.2f} | "
                     f"{total:.2f} | {s['rays_per_second'] / 1e6:.1f} | "
                     f"{s['memory']['peak_rss_mb']:.0f} | {peer_s} | {ratio} |")
    lines.append("")
    m = d_pbrt["mean_rel_diff"]
    lines.append(f"Cornell box 256x256 {rspp} spp vs pbrt-v4 2048 spp: mean rel diff "
                 f"{100*m[0]:+.2f}% {100*m[1]:+.2f}% {100*m[2]:+.2f}%, relMSE {d_pbrt['relmse']:.5f}")
    text = "\n".join(lines)
    print(text)
    if "--no-append" not in sys.argv:
        with open(os.path.join(ROOT, "bench", "history", "log.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/scene_bench.py{' --quick' if quick else ''}`\n\n")
            for _, s, _ in rows:
                f.write(f"    {s['cmd']}\n")
            f.write("\n" + text + "\n")


if __name__ == "__main__":
    main()
