#!/usr/bin/env python3
"""A stage in haze lit by coloured spot lights, written as a pbrt-v4 scene on stdout: a grey
floor and back wall, and a rig of spot lights above the stage, each aimed at its own point of
the floor, in a homogeneous medium that fills the scene (the camera is in it too), so that every
beam shows.

  python3 examples/haze_stage.py [N] [WIDTH HEIGHT] > haze.pbrt      (N: 24 spots by default)
  build/manylight render haze.pbrt --time-limit 60 -o haze.exr
"""
import colorsys
import random
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 24
width = int(sys.argv[2]) if len(sys.argv) > 2 else 320
height = int(sys.argv[3]) if len(sys.argv) > 3 else 180
random.seed(38)
print(f'''MakeNamedMedium "haze" "string type" "homogeneous"
  "rgb sigma_a" [ 0.005 0.005 0.005 ] "rgb sigma_s" [ 0.06 0.06 0.06 ] "float g" [ 0.5 ]
MediumInterface "" "haze"
LookAt 0 2.5 -9  0 1.8 1  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ {width} ] "integer yresolution" [ {height} ]
Sampler "sobol"
Integrator "volpath" "integer maxdepth" [ 6 ]
WorldBegin
MediumInterface "haze" "haze"
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3  4 5 6 4 6 7 ]
    "point3 P" [ -8 0 -10  -8 0 5  8 0 5  8 0 -10   -8 0 5  -8 7 5  8 7 5  8 0 5 ]
AttributeEnd
AttributeBegin
  Material "conductor" "float roughness" [ 0.15 ]
  Translate 0 0.8 1.5
  Shape "sphere" "float radius" [ 0.8 ]
AttributeEnd''')
for k in range(n):
    # The rig: a row of spots across the top of the stage, each aimed at the floor.
    x = -6 + 12 * (k + 0.5) / n
    y, z = 6.5, random.uniform(-1, 3)
    tx, tz = random.uniform(-5, 5), random.uniform(-3, 4)
    cone = random.uniform(8, 14)
    r, g, b = colorsys.hsv_to_rgb(random.random(), random.uniform(0.5, 0.9), 1.0)
    power = 60
    print(f'LightSource "spot" "point3 from" [ {x:.3f} {y:.3f} {z:.3f} ] '
          f'"point3 to" [ {tx:.3f} 0 {tz:.3f} ] "float coneangle" [ {cone:.1f} ] '
          f'"float conedeltaangle" [ 2 ] "rgb I" [ {power * r:.2f} {power * g:.2f} {power * b:.2f} ]')
