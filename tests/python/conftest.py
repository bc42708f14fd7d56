"""Fixtures for the Python module's tests (run by ctest as Python.Pytest, or by hand from the
repository root after scripts/build: /usr/bin/python3 -m pytest tests/python)."""

import os
import pathlib
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(os.environ.get("MANYLIGHT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
if "manylight" not in sys.modules and not os.environ.get("PYTHONPATH"):
    sys.path.insert(0, str(ROOT / "build" / "python"))

# A small box lit by an area light and a point light, with no Integrator of its own, so that
# every integrator renders it with its own defaults.
SCENE = """LookAt 0 1.2 4  0 1 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Sampler "independent" "integer pixelsamples" [ 4 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 16 ]
WorldBegin
Material "diffuse" "rgb reflectance" [ 0.7 0.6 0.5 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -2 0 -1  2 0 -1  2 0 3  -2 0 3 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -2 0 -1  -2 3 -1  2 3 -1  2 0 -1 ]
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.2 0.6 0.2 ]
  Translate 0.5 0.5 0
  Shape "sphere" "float radius" [ 0.5 ]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 8 8 8 ] "bool twosided" true
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -0.5 2.5 -0.5  0.5 2.5 -0.5  0.5 2.5 0.5  -0.5 2.5 0.5 ]
AttributeEnd
LightSource "point" "rgb I" [ 2 2 2 ] "point3 from" [ -1 1.5 1 ]
"""


@pytest.fixture(scope="session")
def scene(tmp_path_factory):
    path = tmp_path_factory.mktemp("scene") / "box.pbrt"
    path.write_text(SCENE)
    return path


@pytest.fixture(scope="session")
def binary():
    path = pathlib.Path(os.environ.get("MANYLIGHT_BINARY", ROOT / "build" / "manylight"))
    if not path.exists():
        pytest.fail(f"the program {path} is not built (scripts/build manylight)")
    return path


def read_pfm(path):
    """A PFM file as a (height, width, 3) float32 array, top row first: read here with numpy,
    independently of the module and of OpenImageIO."""
    data = pathlib.Path(path).read_bytes()
    fields = data.split(maxsplit=4)  # "PF", width, height, scale, pixels
    assert fields[0] == b"PF"
    width, height, scale = int(fields[1]), int(fields[2]), float(fields[3])
    pixels = data[len(data) - width * height * 12 :]
    image = np.frombuffer(pixels, dtype="<f4" if scale < 0 else ">f4").reshape(height, width, 3)
    return np.flipud(image).astype(np.float32)
