#!/usr/bin/env python3
"""Writes a procedural equirectangular sky as a Radiance .hdr (flat RGBE scanlines, which
every Radiance reader accepts): a blue gradient above the horizon, a dim ground below, and a
sun of 0.53 degrees whose radiance gives SUN_IRRADIANCE W/m^2 at normal incidence. For the
environment benches (issue 19); no dependencies.

Usage: python3 sky_hdr.py OUT.hdr [WIDTH] [SUN_IRRADIANCE]"""
import math
import struct
import sys

out = sys.argv[1]
w = int(sys.argv[2]) if len(sys.argv) > 2 else 2048
sun_e = float(sys.argv[3]) if len(sys.argv) > 3 else 20.0
h = w // 2
# The sun: 40 degrees up, towards u = 0.3 (see solari_scene::environment for the mapping).
sun_u, sun_v = 0.3, (90.0 - 40.0) / 180.0
theta_s = math.pi * sun_v
phi_s = (sun_u - 0.5) * 2 * math.pi
sun_d = (math.sin(theta_s) * math.sin(phi_s), math.cos(theta_s), -math.sin(theta_s) * math.cos(phi_s))
radius = math.radians(0.53) / 2
cos_r = math.cos(radius)
# Texels of the disk get radiance E / (pi sin^2 r), spread over at least one texel.
texel_solid = (2 * math.pi / w) * (math.pi / h)
disk_solid = 2 * math.pi * (1 - cos_r)
sun_l = sun_e / max(disk_solid, texel_solid)


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return b"\0\0\0\0"
    e = math.frexp(m)[1]
    s = 256.0 / (2.0 ** e) * (1 - 1e-7)
    return bytes((int(r * s), int(g * s), int(b * s), e + 128))


rows = []
for y in range(h):
    v = (y + 0.5) / h
    theta = math.pi * v
    row = bytearray()
    for x in range(w):
        u = (x + 0.5) / w
        phi = (u - 0.5) * 2 * math.pi
        d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
        if d[1] > 0:
            t = d[1]
            c = (0.35 + 0.3 * (1 - t), 0.55 + 0.25 * (1 - t), 1.0)
        else:
            c = (0.12, 0.1, 0.08)
        cos_s = sum(a * b for a, b in zip(d, sun_d))
        if cos_s > min(cos_r, math.cos(math.sqrt(texel_solid))):
            c = (sun_l, sun_l * 0.95, sun_l * 0.85)
        row += rgbe(*c)
    rows.append(bytes(row))
with open(out, "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
    f.write(f"-Y {h} +X {w}\n".encode())
    for r in rows:
        f.write(r)
