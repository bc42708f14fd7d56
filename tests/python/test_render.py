"""manylight.render against the command line, errors, settings, progress and cancelling."""

import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import manylight
from conftest import read_pfm


def cli_render(binary, tmp_path, scene, args):
    """`manylight render` to a PFM (float, exact) and its --stats; the image and the dict."""
    out, stats = tmp_path / "cli.pfm", tmp_path / "cli.json"
    command = [str(binary), "render"] + ([str(scene)] if scene else []) + args
    subprocess.run(command + ["-q", "-o", str(out), "--stats", str(stats)], check=True)
    return read_pfm(out), json.loads(stats.read_text())


@pytest.mark.parametrize(
    "kwargs, args",
    [
        # Every option given.
        (
            dict(integrator="mdlightcuts", spp=4, resolution=(20, 12), seed=7,
                 settings={"vpl.count": 500, "mdlightcuts.error": 0.05}),
            ["--integrator", "mdlightcuts", "--spp", "4", "--resolution", "20x12", "--seed", "7",
             "--set", "vpl.count=500", "--set", "mdlightcuts.error=0.05"],
        ),
        # The scene's integrator (none: path), spp and resolution, and the default seed.
        (dict(), []),
        (dict(integrator="bdpt", max_depth=3, sampler="sobol", threads=1, seed=3),
         ["--integrator", "bdpt", "--max-depth", "3", "--sampler", "sobol", "--threads", "1",
          "--seed", "3"]),
    ],
)
def test_render_is_the_command_lines_image(binary, tmp_path, scene, kwargs, args):
    image, stats = manylight.render(scene, **kwargs)
    expected, cli_stats = cli_render(binary, tmp_path, scene, args)
    assert image.dtype == np.float32
    assert image.shape == expected.shape == (stats["resolution"][1], stats["resolution"][0], 3)
    assert image.mean() > 0
    assert np.array_equal(image, expected)
    # The command line's bias check (on for the many-light integrators) is its own addition.
    cli_stats.pop("bias_check", None)
    assert stats.keys() == cli_stats.keys()
    for key in ("integrator", "sampler", "spp", "resolution", "rays", "lights", "film"):
        assert stats[key] == cli_stats[key], key


def test_the_built_in_cornell_box(binary, tmp_path):
    image, stats = manylight.render(None, spp=2, resolution=(16, 16))
    expected, cli_stats = cli_render(binary, tmp_path, None, ["--spp", "2", "--resolution", "16x16"])
    assert np.array_equal(image, expected)
    assert stats["integrator"] == cli_stats["integrator"] == "path"


def test_the_same_seed_gives_the_same_image(scene):
    a, _ = manylight.render(scene, spp=2, seed=5, threads=1)
    b, _ = manylight.render(scene, spp=2, seed=5)
    c, _ = manylight.render(scene, spp=2, seed=6)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_a_bad_scene_raises_with_its_location(tmp_path):
    bad = tmp_path / "bad.pbrt"
    bad.write_text('WorldBegin\nMaterial "diffuse"\nShape "nosuchshape"\n')
    with pytest.raises(manylight.InputError) as caught:
        manylight.render(bad, spp=1)
    error = caught.value
    assert isinstance(error, manylight.Error) and isinstance(error, Exception)
    assert error.file == str(bad)
    assert error.line == 3
    assert error.column >= 1
    assert str(error).startswith(f"{bad}:3:{error.column}: ")
    assert "nosuchshape" in str(error)
    assert 'Shape "nosuchshape"' in str(error)  # the line itself, as the command line prints it


def test_a_missing_scene_raises(tmp_path):
    with pytest.raises(manylight.InputError, match="missing.pbrt"):
        manylight.render(tmp_path / "missing.pbrt")


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(spp=0), "spp: expected a positive integer"),
        (dict(resolution=(0, 4)), "resolution"),
        (dict(seed=-1), "seed"),
        (dict(time_limit=-2.0), "time_limit"),
        (dict(sampler="halton"), "sampler"),
        (dict(integrator="nosuch"), 'unknown integrator "nosuch"'),
        (dict(settings={"path.nosuch": 1}), "path.nosuch"),
        (dict(settings={"lightcuts.error": 0.1}), "lightcuts.error"),  # path does not read it
        (dict(integrator="lightcuts", settings={"lightcuts.error": "abc"}), "not a number"),
        (dict(settings={"path.maxdepth": [1]}), "expected a bool, int, float or str"),
    ],
)
def test_bad_arguments_raise_usage_errors(scene, kwargs, message):
    with pytest.raises(manylight.UsageError, match=message) as caught:
        manylight.render(scene, **{"spp": 1, **kwargs})
    assert isinstance(caught.value, ValueError)


# Readme's table of integrators, and defaults the README documents.
INTEGRATORS = ["path", "direct", "whitted", "lighttracer", "bdpt", "mlt", "cmlt", "pssmlt",
               "vpl", "lightcuts", "stochasticlightcuts", "mdlightcuts", "bdlightcuts", "igi"]


def test_integrators_lists_names_settings_and_defaults():
    listed = manylight.integrators()
    assert list(listed) == INTEGRATORS
    for name, entry in listed.items():
        assert entry["summary"]
        assert all(key.count(".") >= 1 for key in entry["settings"]), name
    path = listed["path"]["settings"]
    assert path["path.maxdepth"] == 5 and type(path["path.maxdepth"]) is int
    assert path["path.lightsampler"] == "tree"
    assert path["path.regularize"] is False
    lightcuts = listed["lightcuts"]["settings"]
    assert lightcuts["lightcuts.error"] == 0.1 and type(lightcuts["lightcuts.error"]) is float
    assert lightcuts["lightcuts.max_cut"] == 1000
    assert lightcuts["vpl.count"] == 100000
    assert lightcuts["vpl.clamp"] == 0.0
    assert lightcuts["vpl.sets"] == "pass"
    assert lightcuts["lights.direct"] == "sample"
    md = listed["mdlightcuts"]["settings"]
    assert md["mdlightcuts.samples"] == 32 and md["mdlightcuts.error"] == 0.1
    assert listed["igi"]["settings"]["igi.interleave"] == "4x4"
    assert listed["igi"]["settings"]["vpl.count"] == 256  # igi's own default, as igi.vpls
    assert listed["pssmlt"]["settings"]["pssmlt.large_step_prob"] == 0.3


def test_the_command_line_lists_the_same_settings(binary):
    text = subprocess.run([str(binary), "integrators"], capture_output=True, text=True,
                          check=True).stdout
    listed = {}
    for line in text.splitlines():
        if not line.startswith("  "):
            name = line.split(":")[0]
            listed[name] = {}
        else:
            key, rest = line.strip().split("=", 1)
            listed[name][key] = rest.rsplit(" (", 1)[0]
    expected = manylight.integrators()
    assert list(listed) == list(expected)
    for name, entry in expected.items():
        assert list(listed[name]) == list(entry["settings"]), name
        for key, value in entry["settings"].items():
            text = listed[name][key]
            if isinstance(value, bool):
                assert text == ("true" if value else "false")
            else:
                assert type(value)(text) == value, key


# Settings that make the slow defaults small; the rest keep their listed defaults.
SMALL = {"vpl.count": 300, "igi.vpls": 300, "mlt.bootstrap": 2000, "cmlt.bootstrap": 2000,
         "pssmlt.bootstrap": 2000, "pssmlt.chains": 50, "mlt.chains": 16, "cmlt.chains": 16}


@pytest.mark.parametrize("name", INTEGRATORS)
def test_settings_round_trip(scene, name):
    """Every listed setting is accepted back with its listed default, and gives the image of
    not setting it: the names and the defaults are the integrator's own."""
    defaults = manylight.integrators()[name]["settings"]
    small = {k: v for k, v in SMALL.items() if k in defaults}
    common = dict(integrator=name, spp=2, resolution=(12, 8), seed=2)
    unset, stats = manylight.render(scene, settings=small, **common)
    given, _ = manylight.render(scene, settings={**defaults, **small}, **common)
    assert stats["integrator"] == name
    assert np.array_equal(unset, given)


def test_a_setting_reaches_the_integrator(scene):
    common = dict(integrator="lightcuts", spp=1, resolution=(12, 8), seed=2)
    _, tight = manylight.render(scene, settings={"vpl.count": 2000, "lightcuts.error": 0.001},
                                **common)
    _, loose = manylight.render(scene, settings={"vpl.count": 2000, "lightcuts.error": 0.5},
                                **common)
    assert tight["lights"]["vpls"] == loose["lights"]["vpls"] > 0
    assert tight["rays"]["shadow"] > loose["rays"]["shadow"]


def test_a_scene_integrator_manylight_lacks_warns(tmp_path):
    from conftest import SCENE
    scene = tmp_path / "sppm.pbrt"
    scene.write_text('Integrator "sppm"\n' + SCENE)
    with pytest.warns(manylight.RenderWarning, match="sppm"):
        manylight.render(scene, spp=1)


def test_progress_is_reported(scene):
    seen = []
    manylight.render(scene, spp=100000, time_limit=0.6, resolution=(8, 8), progress=seen.append)
    assert seen == sorted(seen)
    assert 0 < seen[0] and seen[-1] == 1.0
    assert len([f for f in seen if f < 1]) >= 3  # polled every 50 ms during the 0.6 s


class Stop(Exception):
    pass


def test_an_exception_from_the_callback_cancels_the_render(scene):
    def stop(fraction):
        raise Stop

    start = time.monotonic()
    with pytest.raises(Stop):
        manylight.render(scene, spp=100000, time_limit=30, resolution=(8, 8), progress=stop)
    assert time.monotonic() - start < 5


def test_ctrl_c_interrupts_a_render(scene):
    timer = threading.Timer(0.4, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            manylight.render(scene, spp=100000, time_limit=30, resolution=(8, 8))
    finally:
        timer.cancel()
    assert time.monotonic() - start < 5
    # The module renders on afterwards.
    image, stats = manylight.render(scene, spp=1, resolution=(8, 8))
    assert stats["spp"] == 1 and image.mean() > 0


def test_a_cancelled_render_resumes_from_its_checkpoint(tmp_path):
    """Cancelled part way with a checkpoint, then resumed: the uninterrupted image, bit for bit."""
    ckpt = tmp_path / "state.ckpt"
    args = dict(integrator="path", spp=2000, resolution=(24, 16), seed=3, threads=1)

    def stop(fraction):
        if fraction >= 0.3:
            raise Stop

    with pytest.raises(Stop):
        manylight.render(checkpoint=ckpt, progress=stop, **args)
    assert ckpt.exists()
    resumed, stats = manylight.render(resume=ckpt, **args)
    assert 0 <= stats["checkpoint"]["resumed_from"] < 2000
    full, _ = manylight.render(**args)
    assert np.array_equal(full, resumed)
    with pytest.raises(manylight.UsageError, match="spp is 2000 there, 2001 here"):
        manylight.render(resume=ckpt, **dict(args, spp=2001))


def test_read_and_write_image(tmp_path, scene):
    image, _ = manylight.render(scene, spp=1, resolution=(10, 6))
    manylight.write_image(tmp_path / "x.pfm", image)
    assert np.array_equal(read_pfm(tmp_path / "x.pfm"), image)
    assert np.array_equal(manylight.read_image(tmp_path / "x.pfm"), image)
    with pytest.raises(manylight.UsageError):
        manylight.write_image(tmp_path / "y.pfm", np.zeros((4, 4)))
