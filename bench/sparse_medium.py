#!/usr/bin/env python3
"""A sparse grid medium: six dense blobs of smoke in a 4 x 4 x 4 box of 48^3 cells, 85% empty,
over a grey floor under an area light. Most of a ray's way through the box crosses nothing, which
one majorant for the whole box makes delta and ratio tracking step through in small steps; the
majorant grid (media/medium.h) lets them cross the empty cells at once.

Writes the scene, then renders it with each binary given (the same seed and samples), and prints
seconds and the image means, so that two builds (before and after a change) compare in one run:

  bench/sparse_medium.py --bin OLD/manylight --bin build/manylight [--spp 256]
"""
import argparse
import math
import os
import random
import subprocess
import tempfile
import time


def scene(n=48, seed=3):
    rnd = random.Random(seed)
    blobs = [(rnd.uniform(0.2, 0.8), rnd.uniform(0.2, 0.8), rnd.uniform(0.2, 0.8),
              rnd.uniform(0.05, 0.12)) for _ in range(6)]
    vals = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                x, y, z = (i + .5) / n, (j + .5) / n, (k + .5) / n
                d = 0
                for bx, by, bz, r in blobs:
                    q = math.sqrt((x - bx) ** 2 + (y - by) ** 2 + (z - bz) ** 2) / r
                    if q < 1:
                        d = max(d, 8 * (1 - q))
                vals.append('%.3g' % d)
    quad = '"integer indices" [ 0 1 2 0 2 3 ] "point3 P"'
    return f'''LookAt 0 2 -7  0 1.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 160 ] "integer yresolution" [ 120 ]
Integrator "volpath" "integer maxdepth" [ 5 ]
WorldBegin
AttributeBegin
MakeNamedMedium "smoke" "string type" "uniformgrid" "point3 p0" [ -2 0 -2 ] "point3 p1" [ 2 4 2 ]
  "integer nx" [ {n} ] "integer ny" [ {n} ] "integer nz" [ {n} ]
  "float density" [ {' '.join(vals)} ]
  "rgb sigma_a" [ 0.3 0.3 0.3 ] "rgb sigma_s" [ 2 2 2 ] "float g" [ 0.3 ]
AttributeEnd
AttributeBegin
  Translate 0 6 0
  AreaLightSource "diffuse" "rgb L" [ 20 20 20 ]
  Shape "trianglemesh" {quad} [ -1 0 -1  1 0 -1  1 0 1  -1 0 1 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" {quad} [ -8 0 -8  -8 0 8  8 0 8  8 0 -8 ]
AttributeBegin
  MediumInterface "smoke" ""
  Material "interface"
  Translate 0 2.001 0
  Shape "trianglemesh" "integer indices" [ 0 3 2 0 2 1  4 5 6 4 6 7  0 1 5 0 5 4  2 3 7 2 7 6  1 2 6 1 6 5  0 4 7 0 7 3 ]
    "point3 P" [ -2 -2 -2  2 -2 -2  2 2 -2  -2 2 -2  -2 -2 2  2 -2 2  2 2 2  -2 2 2 ]
AttributeEnd
'''


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bin', action='append', required=True, help='a manylight binary (repeat)')
    ap.add_argument('--spp', type=int, default=256)
    ap.add_argument('--threads', type=int, default=2)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, 'sparse.pbrt')
        with open(path, 'w') as f:
            f.write(scene())
        images = []
        for i, b in enumerate(a.bin):
            out = os.path.join(tmp, f'{i}.exr')
            t = time.monotonic()
            subprocess.run([b, 'render', path, '--spp', str(a.spp), '--seed', '1', '--threads',
                            str(a.threads), '-q', '-o', out], check=True)
            print(f'{b}: {time.monotonic() - t:.2f} s')
            images.append(out)
        for out in images[1:]:
            subprocess.run([a.bin[0], 'diff', out, images[0]], check=True)


if __name__ == '__main__':
    main()
