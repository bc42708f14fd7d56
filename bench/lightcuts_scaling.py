#!/usr/bin/env python3
"""Lightcuts scaling (issue: many lights I): tree build time, cut size, render time of
`lightcuts` and of the brute-force `vpl` on the same point-light set, speedup and error
percentiles, as the number of VPLs grows.

The brute force is O(lights) per pixel, so both integrators render a small image for the
comparison (said in the table); `lightcuts` is also timed alone at the larger resolution.
Usage: bench/lightcuts_scaling.py SCENE [--counts 1000,10000,100000] [--glossy bsdf|diffuse|skip]
       [--direct points|sample] [--error 0.02] [--exact-max 100000] [--small 48x27]
       [--small-spp 4] [--defaults] [--no-append]

--defaults: only vpl.count is set; every other setting (vpl.glossy, lights.direct,
lightcuts.error, max_cut, clamp, floor) is the integrators' default, as a user gets it.

--direct sample: the area and infinite lights' direct light by next-event estimation
(lights.direct=sample), so the tree holds the VPLs and the delta lights only.

The large image is rendered by lightcuts alone at 1 spp (cut sizes, times); the small one by both
integrators at --small-spp samples per pixel (speedup, and the per-pixel error of the average of
a pixel's samples, as an image shows it: lightcuts draws each sample's representatives anew).

Speedup is given twice: for the whole render call, and for shading alone (the render less the
point-light set and, for lightcuts, the tree, which only lightcuts builds).
"""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("MANYLIGHT_BIN", os.path.join(ROOT, "build", "manylight"))


def arg(name, default):
    if name in sys.argv:
        return sys.argv[sys.argv.index(name) + 1]
    return default


DIRECT = "points"
ERROR = "0.02"
DEFAULTS = False


def render(scene, integrator, count, res, glossy, tmp, spp=1):
    out = os.path.join(tmp, f"{integrator}-{count}-{res}.pfm")
    stats = out + ".json"
    cmd = [BIN, "render", scene, "-q", "--threads", "2", "--spp", str(spp), "--seed", "1",
           "--resolution", res, "--integrator", integrator, "--set", f"vpl.count={count}",
           "-o", out, "--stats", stats]
    if not DEFAULTS:
        cmd += ["--set", f"vpl.glossy={glossy}", "--set", f"lights.direct={DIRECT}"]
        if integrator == "lightcuts":
            cmd += ["--set", f"lightcuts.error={ERROR}"]
    t0 = time.time()
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        s = json.load(f)
    s["wall"] = time.time() - t0
    s["cmd"] = " ".join(os.path.relpath(c, ROOT) if c.startswith(ROOT) else c for c in cmd)
    s["cmd"] = s["cmd"].replace(tmp, "OUT")
    return out, s


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        import array
        data = array.array("f")
        data.frombytes(f.read())
        if scale > 0:
            data.byteswap()
    return w, h, data


def percentiles(a, b):
    _, _, da = read_pfm(a)
    _, _, db = read_pfm(b)
    rel = []
    for i in range(0, len(da), 3):
        la = 0.2126 * da[i] + 0.7152 * da[i + 1] + 0.0722 * da[i + 2]
        lb = 0.2126 * db[i] + 0.7152 * db[i + 1] + 0.0722 * db[i + 2]
        rel.append(abs(la - lb) / max(lb, 1e-6))
    rel.sort()
    pick = lambda p: rel[int(p * (len(rel) - 1))]
    within = sum(1 for r in rel if r <= 0.02) / len(rel)
    return pick(0.5), pick(0.9), pick(0.99), within


def main():
    global DIRECT, ERROR, DEFAULTS
    DEFAULTS = "--defaults" in sys.argv
    scene = sys.argv[1]
    DIRECT = arg("--direct", "points")
    ERROR = arg("--error", "0.02")
    counts = [int(c) for c in arg("--counts", "1000,10000,100000").split(",")]
    glossy = arg("--glossy", "diffuse")
    exact_max = int(arg("--exact-max", "100000"))
    small, large = arg("--small", "48x27"), "320x180"
    small_spp = int(arg("--small-spp", "4"))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in counts:
            _, big = render(scene, "lightcuts", n, large, glossy, tmp)
            lc_small, lcs = render(scene, "lightcuts", n, small, glossy, tmp, small_spp)
            row = {"n": n, "big": big, "lcs": lcs}
            if n <= exact_max:
                ex_small, exs = render(scene, "vpl", n, small, glossy, tmp, small_spp)
                row["exs"] = exs
                row["pct"] = percentiles(lc_small, ex_small)
            rows.append(row)
    settings = ("the integrators' defaults" if DEFAULTS else
                f"vpl.glossy={glossy}, lights.direct={DIRECT}, error {ERROR}")
    lines = [f"Scene `{os.path.relpath(scene, ROOT)}`, {settings}, 2 threads; "
             f"{large} at 1 spp, {small} at {small_spp} spp.",
             "",
             f"| VPLs | point lights | light set s | tree build s | avg cut | max cut | lightcuts render s ({large}) | lightcuts s ({small}) | vpl s ({small}) | speedup | speedup, shading only | rel. error p50 / p90 / p99 | within 2% |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lc = r["big"]["lightcuts"]
        lcs = r["lcs"]
        exact = r.get("exs")
        sp = f"{exact['seconds']['render'] / lcs['seconds']['render']:.1f}x" if exact else "-"
        sp_shade = "-"
        if exact:
            lc_shade = lcs["seconds"]["render"] - lcs["lightcuts"]["point_light_seconds"] - \
                lcs["lightcuts"]["tree_build_seconds"]
            ex_shade = exact["seconds"]["render"] - lcs["lightcuts"]["point_light_seconds"]
            sp_shade = f"{ex_shade / lc_shade:.1f}x"
        pct = r.get("pct")
        pct_s = f"{pct[0]:.4f} / {pct[1]:.4f} / {pct[2]:.4f}" if pct else "-"
        within = f"{100 * pct[3]:.1f}%" if pct else "-"
        lines.append(
            f"| {r['n']} | {r['big']['lights']['point_lights']} | {lc['point_light_seconds']:.2f} | "
            f"{lc['tree_build_seconds']:.3f} | {lc['avg_cut_size']:.1f} | {lc['max_cut_size']} | "
            f"{r['big']['seconds']['render']:.2f} | {lcs['seconds']['render']:.3f} | "
            f"{exact['seconds']['render'] if exact else float('nan'):.3f} | {sp} | {sp_shade} | {pct_s} | {within} |")
    text = "\n".join(lines)
    print(text)
    if "--no-append" not in sys.argv:
        with open(os.path.join(ROOT, "bench", "history", "log.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/lightcuts_scaling.py {' '.join(sys.argv[1:])}`\n\n")
            f.write("    " + rows[0]["big"]["cmd"] + "\n\n" + text + "\n")


if __name__ == "__main__":
    main()
