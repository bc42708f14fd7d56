#!/usr/bin/env python3
"""--time-limit as a contract (issue 11): every integrator on kitchen and cornell-box with
--time-limit T (default 5 s) at 320x180, default settings; prints the render phase's seconds
(from --stats) and the whole wall time, and flags any render phase over T + 10%.

Usage: bench/time_limit.py [--seconds 5] [--bin build/manylight] [--scenes kitchen,cornell-box]
"""
import argparse
import json
import os
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INTEGRATORS = ["path", "direct", "whitted", "lighttracer", "bdpt", "mlt", "cmlt", "pssmlt", "vpl",
               "lightcuts", "mdlightcuts"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--scenes", default="kitchen,cornell-box")
    ap.add_argument("--integrators", default=",".join(INTEGRATORS))
    args = ap.parse_args()
    limit = args.seconds
    print(f"| scene | integrator | render phase (s) | wall (s) | spp | within {limit} s + 10% |")
    print("|---|---|---|---|---|---|")
    over = 0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes.split(","):
            path = os.path.join(ROOT, "..", "shared", "scenes", scene, "scene-v4.pbrt")
            for integ in args.integrators.split(","):
                stats = os.path.join(tmp, "s.json")
                cmd = [args.bin, "render", path, "--integrator", integ, "--resolution", "320x180",
                       "--time-limit", str(limit), "-q", "-o", os.path.join(tmp, "o.exr"),
                       "--stats", stats]
                t0 = time.time()
                subprocess.run(cmd, check=True)
                wall = time.time() - t0
                with open(stats) as f:
                    s = json.load(f)
                render = s["seconds"]["render"]
                ok = render <= 1.1 * limit
                over += not ok
                print(f"| {scene} | {integ} | {render:.2f} | {wall:.2f} | {s['spp']} | "
                      f"{'yes' if ok else 'NO'} |", flush=True)
    return 1 if over else 0


if __name__ == "__main__":
    raise SystemExit(main())
