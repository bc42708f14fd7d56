#!/usr/bin/env python3
"""A coloured many-light test scene (issue 13, item 1) on stdout: 4096 point lights in a 64 x 64
grid at height 1 over a grey diffuse plane, seen from above at 32x32.

  rg:   pure red and pure green, alternating (half each, mixed in space)
  rand: random colours (seeded)

Usage: bench/coloured_grid_scene.py rg > /tmp/rg.pbrt
       build/manylight render /tmp/rg.pbrt --integrator lightcuts --spp 16 --set vpl.count=0 \
           --seed N -o lc.exr
       build/manylight render /tmp/rg.pbrt --integrator vpl --spp 16 --set vpl.count=0 -o vpl.exr
       build/manylight diff lc.exr vpl.exr
"""
import random
import sys

mode = sys.argv[1] if len(sys.argv) > 1 else "rg"
random.seed(1)
print('''LookAt 0 3 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ]
Sampler "independent"
WorldBegin''')
for i in range(64):
    for j in range(64):
        x, z = -2 + 4 * (i + 0.5) / 64, -2 + 4 * (j + 0.5) / 64
        if mode == "rg":
            c = (0.002, 0, 0) if (i + j) % 2 == 0 else (0, 0.002, 0)
        else:
            c = tuple(0.004 * random.random() for _ in range(3))
        print(f'AttributeBegin\n LightSource "point" "rgb I" [ {c[0]} {c[1]} {c[2]} ] '
              f'"point3 from" [ {x} 1.0 {z} ]\nAttributeEnd')
print('''AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ]
AttributeEnd''')
