#!/usr/bin/env python3
"""Path guiding at equal time: `path` with path.guiding=off and =on under one time limit per
scene, relMSE against our own `path` reference.

Usage:
  bench/guiding.py [--time 20] [--scenes classroom,veach-ajar,kitchen,staircase]
                   [--bin build/manylight] [--refs /work/refs] [--seed 1]

References are REFS/SCENE-WxH.exr (our `path` at high spp).
"""
import argparse
import json
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = {
    "classroom": "320x180",
    "veach-ajar": "256x256",
    "kitchen": "320x180",
    "staircase": "180x320",
}


def diff(binary, image, reference):
    out = subprocess.run([binary, "diff", image, reference, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["relmse"]


def ours(binary, scene_file, res, seconds, guiding, seed, out):
    stats = out + ".json"
    cmd = [binary, "render", scene_file, "--integrator", "path", "--resolution", res,
           "--time-limit", str(seconds), "--seed", str(seed), "--threads", "2", "-q", "-o", out,
           "--stats", stats, "--set", f"path.guiding={guiding}"]
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--time", type=float, default=20)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--refs", default="/work/refs")
    ap.add_argument("--shared", default=os.path.join(ROOT, "..", "shared"))
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="guiding-")
    print("| scene | time | off: spp, relMSE | on: spp, relMSE | on / off | training passes "
          "(spp: seconds) | refine s |")
    print("|---|---|---|---|---|---|---|")
    for scene in a.scenes.split(","):
        res = SCENES[scene]
        scene_file = os.path.join(a.shared, "scenes", scene, "scene-v4.pbrt")
        ref = os.path.join(a.refs, f"{scene}-{res}.exr")
        row = {}
        for guiding in ("off", "on"):
            out = os.path.join(tmp, f"{scene}-{guiding}.exr")
            st = ours(a.bin, scene_file, res, a.time, guiding, a.seed, out)
            row[guiding] = (st, diff(a.bin, out, ref))
        off, on = row["off"], row["on"]
        g = on[0].get("integrator_stats", on[0]).get("guiding", {})
        passes = ", ".join(f"{p['spp']}: {p['seconds']:.2f}" for p in g.get("passes", []))
        print(f"| {scene} {res} | {a.time:g} s | {off[0].get('spp')}, {off[1]:.4g} | "
              f"{on[0].get('spp')}, {on[1]:.4g} | {on[1] / off[1]:.2f} | {passes} | "
              f"{g.get('refine_seconds', 0):.2f}|", flush=True)


if __name__ == "__main__":
    main()
