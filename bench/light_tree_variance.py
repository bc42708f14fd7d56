#!/usr/bin/env python3
"""Per-sample variance and time of `path` with the tree light sampler against `power` (issue 14,
item 4).

For each scene and sampler, two renders with different seeds at the same spp; the per-pixel
variance of one render is (a - b)^2 / 2, so the estimate is unbiased whatever the renders
converge to. Printed per scene: the relative variance per sample,
mean((a - b)^2 / 2 / (r^2 + 0.01)) * spp, r a separate render at --ref-spp (tree sampler, seed
99; relMSE's normalisation, with a denominator independent of a and b so that fireflies count
fully), its ratio tree / power, the CPU time per sample (user + system, all threads; less a 1-spp render's, which
loads the scene) and the
efficiency ratio (variance x time).
Samplers are alternated within a scene so that load on the machine hits both.

Usage: bench/light_tree_variance.py [--spp N] [--ref-spp N] [--threads T] [scene ...]
  scenes: cornell-4096pl, kitchen, classroom (default: all three)
"""
import os
import resource
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "manylight")
SCENES_DIR = os.path.join(ROOT, "..", "shared", "scenes")

SCENES = {
    "cornell-4096pl": ("cornell-box/scene-pointlights-4096.pbrt", "256x256"),
    "kitchen": ("kitchen/scene-v4.pbrt", "320x180"),
    "classroom": ("classroom/scene-v4.pbrt", "320x180"),
}


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        assert kind == b"PF", kind
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        fmt = "<" if scale < 0 else ">"
        data = f.read()
    return struct.unpack(fmt + "%df" % (w * h * 3), data[: w * h * 12])


def render(scene, res, sampler, seed, spp, threads, out):
    cmd = [BIN, "render", scene, "-q", "--resolution", res, "--spp", str(spp), "--threads",
           str(threads), "--seed", str(seed), "--set", "path.lightsampler=" + sampler, "-o", out]
    # CPU time (user + system) of the render: on a shared machine wall time mostly measures the
    # other users' load.
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def rel_variance(a, b, ref, spp):
    s = 0.0
    for x, y, r in zip(a, b, ref):
        s += 0.5 * (x - y) ** 2 / (r * r + 0.01)
    return s / len(a) * spp


def main():
    args = sys.argv[1:]
    spp, threads, ref_spp = 8, 2, 32
    if "--ref-spp" in args:
        i = args.index("--ref-spp")
        ref_spp = int(args[i + 1])
        del args[i : i + 2]
    if "--spp" in args:
        i = args.index("--spp")
        spp = int(args[i + 1])
        del args[i : i + 2]
    if "--threads" in args:
        i = args.index("--threads")
        threads = int(args[i + 1])
        del args[i : i + 2]
    names = args or list(SCENES)
    print("| scene | spp | power: rel. var. per sample | tree | tree / power | "
          "CPU s per spp power / tree | efficiency tree / power |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            rel, res = SCENES[name]
            scene = os.path.join(SCENES_DIR, rel)
            var, secs = {}, {}
            for sampler in ["power", "tree"]:
                var[sampler], secs[sampler] = 0.0, 0.0
            imgs = {}
            ref_out = os.path.join(tmp, "%s-ref.pfm" % name)
            render(scene, res, "tree", 99, ref_spp, threads, ref_out)
            ref = read_pfm(ref_out)
            # Alternate: power seed 1, tree seed 1, power seed 2, tree seed 2.
            for seed in [1, 2]:
                for sampler in ["power", "tree"]:
                    out = os.path.join(tmp, "%s-%s-%d.pfm" % (name, sampler, seed))
                    secs[sampler] += render(scene, res, sampler, seed, spp, threads, out)
                    imgs[(sampler, seed)] = read_pfm(out)
            # Loading and building the scene cost the same for both: a 1-spp render of each
            # takes them out of the time per sample.
            for sampler in ["power", "tree"]:
                out = os.path.join(tmp, "%s-%s-1spp.pfm" % (name, sampler))
                base = render(scene, res, sampler, 3, 1, threads, out)
                var[sampler] = rel_variance(imgs[(sampler, 1)], imgs[(sampler, 2)], ref, spp)
                secs[sampler] = (secs[sampler] / 2 - base) / (spp - 1)
            r = var["tree"] / var["power"]
            eff = var["tree"] * secs["tree"] / (var["power"] * secs["power"])
            print("| %s | %d | %.4g | %.4g | **%.3f** | %.3f / %.3f | %.3f |" %
                  (name, spp, var["power"], var["tree"], r, secs["power"], secs["tree"], eff),
                  flush=True)


if __name__ == "__main__":
    main()
