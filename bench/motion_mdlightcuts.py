#!/usr/bin/env python3
"""Multidimensional Lightcuts over time (issue 17): the cost of motion blur.

The motion-blur Cornell box (shutter [0, 1]: a sphere crossing the room, the short box turning)
against the same scene frozen at the middle of the shutter (shutteropen = shutterclose = 0.5),
both by `mdlightcuts` with 16 camera samples per pixel pass (each sample with its own time in
the blurred scene). For each scene a reference of the same integrator, settings and VPL set at
--ref-spp samples per pixel (another pixel seed, same vpl.seed) measures the error of the renders
(relMSE per channel, mean over pixels: (a - ref)^2 / (ref^2 + 1e-3)), so that the error counted is
the cut's and the pixel samples' (antialiasing, time, direct light), not the VPL set's, which all
share.

Cost at the same error: renders' error falls as 1 / time, so the ratio of time x relMSE (motion
over static) is the time the motion-blurred render needs to reach the static one's error. The
renders alternate static and motion, --repeats times, in one run.

--kitchen: the kitchen (../shared/scenes/kitchen/scene-v4.pbrt) with a moving object added: a
grey sphere of radius 0.15 in front of the counters, moving 0.6 along the camera's right while
the shutter is open (the camera gets shutter [0, 1], the pbrt-v4 default, written out so that the
static copy can close it at 0.5). The scene is written to a temporary folder beside links to the
kitchen's models and textures (its relative paths are resolved against the main file's folder).

Usage: bench/motion_mdlightcuts.py [--res 96x96] [--spp 16] [--ref-spp 512] [--repeats 3]
       [--scene PATH | --kitchen] [--threads 2]
"""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("MANYLIGHT_BIN", os.path.join(ROOT, "build", "manylight"))
SHUTTER = '"float shutteropen" [ 0 ] "float shutterclose" [ 1 ]'


def arg(name, default):
    if name in sys.argv:
        return sys.argv[sys.argv.index(name) + 1]
    return default


def read_pfm(path):
    import array
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = array.array("f")
        data.frombytes(f.read())
        if scale > 0:
            data.byteswap()
    return data


def rel_mse(a, b):
    da, db = read_pfm(a), read_pfm(b)
    return sum((x - y) ** 2 / (y * y + 1e-3) for x, y in zip(da, db)) / len(da)


KITCHEN = os.path.join(ROOT, "..", "shared", "scenes", "kitchen")
KITCHEN_CAMERA = 'Camera "perspective"\n    "float fov" [ 35.9834 ]'
# Added at the end of the kitchen's world: the sphere's centre moves by 0.6 along the camera's
# right vector (0.899, 0, -0.438) over the shutter, around a point 2.5 in front of the camera.
KITCHEN_SPHERE = """
AttributeBegin
    ActiveTransform StartTime
    Translate -0.15 1.2 1.75
    ActiveTransform EndTime
    Translate 0.39 1.2 1.49
    ActiveTransform All
    Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
    Shape "sphere" "float radius" [ 0.15 ]
AttributeEnd
"""


def kitchen_motion(tmp):
    """Writes the kitchen with a moving sphere into tmp (beside links to its folders)."""
    for entry in os.listdir(KITCHEN):
        if os.path.isdir(os.path.join(KITCHEN, entry)):
            os.symlink(os.path.abspath(os.path.join(KITCHEN, entry)), os.path.join(tmp, entry))
    text = open(os.path.join(KITCHEN, "scene-v4.pbrt")).read()
    assert KITCHEN_CAMERA in text, "the kitchen's camera line was not found"
    text = text.replace(KITCHEN_CAMERA, KITCHEN_CAMERA + " " + SHUTTER) + KITCHEN_SPHERE
    return text


def render(scene, out, spp, seed, res, threads):
    stats = out + ".json"
    cmd = [BIN, "render", scene, "-q", "--threads", threads, "--spp", str(spp), "--seed",
           str(seed), "--resolution", res, "--integrator", "mdlightcuts", "--set",
           "mdlightcuts.samples=16", "--set", "vpl.seed=7", "-o", out, "--stats", stats]
    t0 = time.time()
    subprocess.run(cmd, check=True)
    wall = time.time() - t0
    with open(stats) as f:
        s = json.load(f)
    s["wall"] = wall
    s["cmd"] = " ".join(cmd)
    return s


def main():
    res = arg("--res", "96x96")
    spp = int(arg("--spp", "16"))
    ref_spp = int(arg("--ref-spp", "512"))
    repeats = int(arg("--repeats", "3"))
    threads = arg("--threads", "2")
    scene = arg("--scene", os.path.join(ROOT, "..", "shared", "scenes", "cornell-box",
                                        "scene-motion-blur.pbrt"))
    with tempfile.TemporaryDirectory() as tmp:
        if "--kitchen" in sys.argv:
            text = kitchen_motion(tmp)
        else:
            text = open(scene).read()
        assert SHUTTER in text, "the scene's shutter line was not found"
        scenes = {"motion": os.path.join(tmp, "motion.pbrt"),
                  "static": os.path.join(tmp, "static.pbrt")}
        with open(scenes["motion"], "w") as f:
            f.write(text)
        with open(scenes["static"], "w") as f:
            f.write(text.replace(SHUTTER, '"float shutteropen" [ 0.5 ] "float shutterclose" [ 0.5 ]'))
        refs = {}
        for name in ("static", "motion"):
            refs[name] = os.path.join(tmp, name + "-ref.pfm")
            render(scenes[name], refs[name], ref_spp, 999, res, threads)
        rows = {"static": [], "motion": []}
        for r in range(repeats):
            for name in ("static", "motion"):
                out = os.path.join(tmp, f"{name}-{r}.pfm")
                s = render(scenes[name], out, spp, 1 + r, res, threads)
                md = s.get("mdlightcuts", {})
                # Shading alone: the render less the point lights and the light tree, which do
                # not depend on the camera's samples.
                shade = (s["seconds"]["render"] - md.get("point_light_seconds", 0) -
                         md.get("tree_build_seconds", 0))
                rows[name].append({"wall": s["wall"], "render": shade,
                                   "err": rel_mse(out, refs[name]),
                                   "rays": md.get("shadow_rays_per_pixel", 0),
                                   "cut": md.get("avg_cut_size", 0),
                                   "cmd": s["cmd"].replace(tmp, "OUT"), "stats": md})
    mean = lambda xs: sum(xs) / len(xs)
    print(f"res {res}, spp {spp} (16 samples per pass), reference {ref_spp} spp, "
          f"{repeats} repeats, threads {threads}")
    print("| scene | shading s | shadow rays / pixel | cut (pairs) | relMSE | shading s x relMSE |")
    print("|---|---:|---:|---:|---:|---:|")
    eff = {}
    for name in ("static", "motion"):
        t = mean([x["render"] for x in rows[name]])
        e = mean([x["err"] for x in rows[name]])
        eff[name] = t * e
        print(f"| {name} | {t:.2f} | {mean([x['rays'] for x in rows[name]]):.0f} | "
              f"{mean([x['cut'] for x in rows[name]]):.0f} | {e:.5f} | {t * e:.5f} |")
    print(f"cost of motion blur at equal error: {eff['motion'] / eff['static']:.2f}x")
    print("shading time ratio (same spp): "
          f"{mean([x['render'] for x in rows['motion']]) / mean([x['render'] for x in rows['static']]):.2f}x")
    print("command:", rows["motion"][0]["cmd"])
    print("mdlightcuts stats (motion, first):", json.dumps(rows["motion"][0]["stats"])[:600])
    print("mdlightcuts stats (static, first):", json.dumps(rows["static"][0]["stats"])[:600])


if __name__ == "__main__":
    main()
