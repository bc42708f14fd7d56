#!/usr/bin/env python3
"""Writes the small 8-bit PNG images of the light reference scenes (light_*.pbrt) and the normal
map of mat_normalmap.pbrt: pure Python, so that anyone can remake them.
python3 make_light_images.py (in this folder)."""
import math
import struct
import zlib


def write_png(path, width, height, channels, pixel):
    """pixel(x, y) -> tuple of `channels` ints in [0, 255]; rows top first."""
    raw = bytearray()
    for y in range(height):
        raw.append(0)
        for x in range(width):
            raw.extend(pixel(x, y))
    colour = {1: 0, 3: 2}[channels]

    def chunk(tag, data):
        body = tag + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(bytes(raw), 9)))
        f.write(chunk(b"IEND", b""))


def clamp(v):
    return max(0, min(255, int(round(v))))


# Goniometric: 32x32 grey equal-area map, smooth and lopsided (brighter towards the square's
# left and top, and a bright patch off-centre), so that a wrong frame or flip shows.
def gonio(x, y):
    u, v = (x + 0.5) / 32, (y + 0.5) / 32
    g = 40 + 120 * (1 - u) + 60 * (1 - v)
    if (u - 0.3) ** 2 + (v - 0.65) ** 2 < 0.02:
        g += 80
    return (clamp(g),)


# Projection: 24x16 RGB slide: red left third, green middle, blue right, a white top band and a
# dark square at the lower right, so that flips and the aspect show.
def slide(x, y):
    if y < 4:
        return (230, 230, 230)
    if x >= 17 and y >= 10:
        return (20, 20, 20)
    if x < 8:
        return (220, 60, 40)
    if x < 16:
        return (50, 200, 70)
    return (40, 80, 230)


# Area light: 16x16 RGB: a warm-to-cool ramp along u, darker towards the bottom (v small in
# texture space), and a black cross, so that u, v and the 1 - v flip show.
def emit(x, y):
    t = (x + 0.5) / 16
    s = 1 - (y + 0.5) / 16
    k = 0.35 + 0.65 * (1 - s)
    if x in (7, 8) or y in (7, 8):
        return (0, 0, 0)
    return (clamp(255 * k * (1 - 0.6 * t)), clamp(255 * k * 0.7), clamp(255 * k * (0.3 + 0.7 * t)))


# Portal sky: 32x32 RGB equal-area map: a bluish sky brighter towards the square's top left, a
# warm sun patch off-centre and a dark band, so that the portal's rectified resampling shows.
def sky(x, y):
    u, v = (x + 0.5) / 32, (y + 0.5) / 32
    r, g, b = 60 + 80 * (1 - u), 90 + 70 * (1 - v), 170 + 60 * (1 - u)
    if (u - 0.62) ** 2 + (v - 0.4) ** 2 < 0.012:
        r, g, b = 255, 230, 160
    if 0.7 < u < 0.78:
        r, g, b = 0.3 * r, 0.3 * g, 0.3 * b
    return (clamp(r), clamp(g), clamp(b))


# Normal map: 64x64 tangent-space normals (r, g, b = (n + 1) / 2): a 4x4 grid of round bumps
# leaning left and up (x and y both matter), and a ridge along the image's top rows, so that a
# wrong axis, sign or the 1 - v flip shows.
def normals(x, y):
    u, v = (x + 0.5) / 64, (y + 0.5) / 64
    cu, cv = (u * 4) % 1 - 0.5, (v * 4) % 1 - 0.5
    r2 = cu * cu + cv * cv
    nx = ny = 0.0
    if r2 < 0.16:
        h = math.sqrt(0.16 - r2)
        nx, ny = 1.2 * cu / h if h > 0.05 else 0, -0.8 * cv / h if h > 0.05 else 0
    if v < 0.12:
        nx += 0.9
    nz = 1.0
    n = math.sqrt(nx * nx + ny * ny + nz * nz)
    return tuple(clamp(255 * (c / n + 1) / 2) for c in (nx, ny, nz))


write_png("light_goniometric.png", 32, 32, 1, gonio)
write_png("light_projection.png", 24, 16, 3, slide)
write_png("light_area_image.png", 16, 16, 3, emit)
write_png("light_portal_sky.png", 32, 32, 3, sky)
write_png("mat_normalmap.png", 64, 64, 3, normals)
