#!/usr/bin/env python3
"""Writes the synthetic measured materials of the tests (pbrt-v4's "measured", RGL .bsdf tensor
files): a GGX microfacet BRDF tabulated in Dupuy and Jakob's parameterisation, with a coloured
spectrum that varies over the luminance warp's domain (8 x 8) and with the incident angle. No RGL data
ships with manylight; pbrt-v4 reads these files as it reads the database's.

    tests/scenes/make_measured_bsdf.py   (writes mat_measured.bsdf and measured_aniso.bsdf here)
"""
import math
import os
import struct

PI = math.pi


def u2theta(u):
    return u * u * PI / 2


def u2phi(u):
    return (2 * u - 1) * PI


def ggx(alpha_x, alpha_y, theta, phi):
    c = math.cos(theta)
    if c <= 1e-7:
        return 0.0
    t2 = math.tan(theta) ** 2
    e = t2 * (math.cos(phi) ** 2 / alpha_x ** 2 + math.sin(phi) ** 2 / alpha_y ** 2)
    return 1 / (PI * alpha_x * alpha_y * c ** 4 * (1 + e) ** 2)


def projected_area(alpha_x, alpha_y, theta, phi):
    # cos(theta) (1 + Lambda): the Smith GGX projected area of the microsurface.
    a2 = (math.cos(phi) * alpha_x) ** 2 + (math.sin(phi) * alpha_y) ** 2
    c, s = math.cos(theta), math.sin(theta)
    return 0.5 * (c + math.sqrt(c * c + a2 * s * s))


def direction(theta, phi):
    return (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))


def write_tensor_file(path, fields):
    # fields: (name, dtype code, shape, packed bytes); dtype 1 = uint8, 10 = float32.
    header = b"tensor_file\0" + bytes([1, 0]) + struct.pack("<I", len(fields))
    size = len(header) + sum(2 + len(n) + 2 + 1 + 8 + 8 * len(s) for n, _, s, _ in fields)
    table, data = b"", b""
    for name, dtype, shape, payload in fields:
        table += struct.pack("<H", len(name)) + name.encode() + struct.pack("<HBQ", len(shape),
                                                                           dtype, size + len(data))
        table += b"".join(struct.pack("<Q", n) for n in shape)
        data += payload
    with open(path, "wb") as f:
        f.write(header + table + data)


def floats(values):
    return struct.pack("<%df" % len(values), *values)


def make(path, alpha_x, alpha_y, phi_i, theta_deg, nm, reflectance, grid):
    iso = len(phi_i) <= 2
    theta_i = [math.radians(t) for t in theta_deg]
    nx, ny = grid
    xs = [x / (nx - 1) for x in range(nx)]
    ys = [y / (ny - 1) for y in range(ny)]
    ndf = [ggx(alpha_x, alpha_y, u2theta(x), u2phi(y)) for y in ys for x in xs]
    sigma = [projected_area(alpha_x, alpha_y, u2theta(x), u2phi(y)) for y in ys for x in xs]
    vndf, lum, spectra = [], [], []
    for po in phi_i:
        for to in theta_i:
            wo = direction(to, po)
            s_o = projected_area(alpha_x, alpha_y, to, po)
            for y in ys:
                for x in xs:
                    tm = u2theta(x)
                    pm = u2phi(y) + (po if iso else 0)
                    wm = direction(tm, pm)
                    cos_om = max(0.0, sum(a * b for a, b in zip(wo, wm)))
                    jac = 2 * PI * PI * x * math.sin(tm)
                    vndf.append(cos_om * ggx(alpha_x, alpha_y, tm, pm) / s_o * jac)
            lum_grid = [0.6 + 0.4 * x / 7 + 0.2 * y / 7 for y in range(8) for x in range(8)]
            lum += lum_grid
            grazing = 0.85 + 0.15 * math.sin(to) ** 2
            for r in reflectance:
                spectra += [r * v * grazing for v in lum_grid]
    n_phi, n_theta = len(phi_i), len(theta_i)
    desc = b"synthetic GGX (alpha %g x %g) for manylight's tests" % (alpha_x, alpha_y)
    write_tensor_file(path, [
        ("description", 1, [len(desc)], desc),
        ("jacobian", 1, [1], bytes([1])),
        ("theta_i", 10, [n_theta], floats(theta_i)),
        ("phi_i", 10, [n_phi], floats(phi_i)),
        ("wavelengths", 10, [len(nm)], floats(nm)),
        ("ndf", 10, [ny, nx], floats(ndf)),
        ("sigma", 10, [ny, nx], floats(sigma)),
        ("vndf", 10, [n_phi, n_theta, ny, nx], floats(vndf)),
        ("luminance", 10, [n_phi, n_theta, 8, 8], floats(lum)),
        ("spectra", 10, [n_phi, n_theta, len(nm), 8, 8], floats(spectra)),
    ])


here = os.path.dirname(os.path.abspath(__file__))
nm = [380.0 + 50 * k for k in range(8)]
# An orange-red reflectance, smooth in wavelength.
orange = [0.25 + 0.55 * math.exp(-((l - 610) / 70) ** 2) for l in nm]
make(os.path.join(here, "mat_measured.bsdf"), 0.25, 0.25, [0.0],
     [0, 10, 20, 30, 40, 50, 60, 70, 80, 89], nm, orange, (32, 16))
make(os.path.join(here, "measured_aniso.bsdf"), 0.15, 0.4,
     [-PI + 2 * PI * k / 6 for k in range(7)], [0, 20, 40, 60, 75, 89],
     [450.0, 550.0, 650.0], [0.3, 0.6, 0.8], (16, 16))
