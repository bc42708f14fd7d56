#!/usr/bin/env python3
"""A stage lit by many coloured spot lights (issue 34, item 5) on stdout: a grey floor and back
wall (4 triangles), and a rig of spot lights 4 units above the floor, each aimed at its own
random point of the floor with a narrow cone (6 to 15 degrees) and a saturated colour. Most
spots light only a small patch, and from any point of the floor most of them face away.

Usage: bench/spot_stage_scene.py [N] [WIDTH HEIGHT] > /tmp/spots.pbrt   (N: 192 by default)
       build/manylight render /tmp/spots.pbrt --integrator stochasticlightcuts --spp 16 -o s.exr
See bench/stochastic_spots.md.
"""
import colorsys
import math
import random
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 192
width = int(sys.argv[2]) if len(sys.argv) > 2 else 160
height = int(sys.argv[3]) if len(sys.argv) > 3 else 90
random.seed(34)
print(f'''LookAt 0 3 -8  0 0.8 1  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ {width} ] "integer yresolution" [ {height} ]
Sampler "independent"
WorldBegin
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3  4 5 6 4 6 7 ]
    "point3 P" [ -6 0 -4  6 0 -4  6 0 5  -6 0 5   -6 0 5  6 0 5  6 5 5  -6 5 5 ]
AttributeEnd''')
cols = max(1, round(math.sqrt(n * 2)))
for k in range(n):
    # The rig: rows of spots over the stage, x in [-4, 4], z in [-2, 3].
    i, j = k % cols, k // cols
    rows = (n + cols - 1) // cols
    x = -4 + 8 * (i + 0.5) / cols
    z = -2 + 5 * (j + 0.5) / rows
    tx, tz = random.uniform(-4.5, 4.5), random.uniform(-2.5, 4.5)
    cone = random.uniform(6, 15)
    delta = random.uniform(1, 3)
    r, g, b = colorsys.hsv_to_rgb(random.random(), random.uniform(0.6, 1.0), 1.0)
    s = random.uniform(1.5, 4.0)
    print(f'LightSource "spot" "rgb I" [ {r * s:.4f} {g * s:.4f} {b * s:.4f} ] '
          f'"point3 from" [ {x:.3f} 4 {z:.3f} ] "point3 to" [ {tx:.3f} 0 {tz:.3f} ] '
          f'"float coneangle" [ {cone:.2f} ] "float conedeltaangle" [ {delta:.2f} ]')
