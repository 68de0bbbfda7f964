#!/usr/bin/env python3
"""The gold sphere's light on sun_boxes' ground, exactly two bounces, by numerical integration
(this folder's README, section 2), against the reference path tracer and path GI.

For each ground pixel of a crop near the sphere (every third pixel of rows 60-150, columns
90-200 at 320x180, where the primary ray hits the ground: `instance` view id 0) the ground
point P is found from the camera; the irradiance at P from the sun's light reflected by the
sphere (centre (-0.4, 0.8, 0.6), radius 0.8) is integrated over 400,000 points of the sphere:
f(wo, wi_sun) cos_sun E_sun cos_S cos_P / r^2 dA, with single-scattering GGX (roughness 0.25,
Schlick Fresnel from the gold base colour; multiple scattering is under 1% at this roughness)
for the gold sphere and base colour / pi for a Lambertian one; other occluders are ignored. P
reflects it with albedo 0.5 / pi (the ground's coat is ignored). Printed: the mean radiance of
both cases and their difference, against the reference's glossy-minus-Lambertian difference
(`--min-bounces 2 --max-bounces 2`), and the same difference in the all-bounce references and
in path GI's means.

Usage: caustic.py DIR  (DIR holds inst.exr, r2_sun_boxes.exr, r2_lambert.exr,
ref_sun_boxes.exr, ref_lambert.exr, m_sun_boxes.exr and m_lambert.exr: the README's renders)
"""
import sys
import numpy as np
import OpenEXR


def load(path):
    ch = OpenEXR.File(path).channels()
    rgb = ch["RGB"].pixels if "RGB" in ch else np.stack([ch[c].pixels for c in "RGB"], -1)
    return rgb.astype(np.float64)


W, H = 320, 180
Q = np.array([-0.123858351, 0.236971502, 0.030475226, 0.963106887])  # camera rotation, xyzw
EYE = np.array([5.5, 4.0, 10.0])
TAN = np.tan(0.6981317 / 2)
CENTRE, RADIUS = np.array([-0.4, 0.8, 0.6]), 0.8
SUN = -np.array([-0.451, -0.752, -0.481]) / np.linalg.norm([-0.451, -0.752, -0.481])
E_SUN = 4 * np.array([1.0, 0.95, 0.88])
GOLD, ALPHA = np.array([1.0, 0.766, 0.336]), 0.25**2


def rotate(v):
    u, w = Q[:3], Q[3]
    return 2 * np.dot(u, v) * u + (w * w - np.dot(u, u)) * v + 2 * w * np.cross(u, v)


FWD, UP, RIGHT = rotate(np.array([0, 0, -1.0])), rotate(np.array([0, 1.0, 0])), rotate(np.array([1.0, 0, 0]))


def ground_pixels(inst):
    """(row, column, P) for the crop's ground pixels."""
    out = []
    for j in range(60, 150, 3):
        for i in range(90, 200, 3):
            if inst[j, i] != 0:
                continue
            x = (2 * (i + 0.5) / W - 1) * TAN * W / H
            y = (1 - 2 * (j + 0.5) / H) * TAN
            d = FWD + x * RIGHT + y * UP
            d /= np.linalg.norm(d)
            if d[1] < 0:
                out.append((j, i, EYE + d * (-EYE[1] / d[1])))
    return out


def sphere_light(points):
    rng = np.random.default_rng(1)
    n_samples = 400_000
    z = rng.uniform(-1, 1, n_samples)
    phi = rng.uniform(0, 2 * np.pi, n_samples)
    s = np.sqrt(1 - z * z)
    n = np.stack([s * np.cos(phi), z, s * np.sin(phi)], -1)
    pos = CENTRE + RADIUS * n
    area = 4 * np.pi * RADIUS**2 / n_samples
    cos_sun = n @ SUN
    glossy, lambert = [], []
    for p in points:
        v = p - pos
        r = np.linalg.norm(v, axis=-1)
        wo = v / r[:, None]
        cos_s = np.sum(n * wo, -1)
        cos_p = -wo[:, 1]
        ok = (cos_sun > 0) & (cos_s > 0) & (cos_p > 0)
        geo = np.where(ok, cos_s * cos_p / (r * r), 0) * area
        h = wo + SUN
        h /= np.linalg.norm(h, axis=-1, keepdims=True)
        c_h = np.clip(np.sum(n * h, -1), 0, 1)
        i_h = np.clip(h @ SUN, 0, 1)
        a2 = ALPHA * ALPHA
        d = a2 / (np.pi * ((1 - c_h * c_h) + a2 * c_h * c_h) ** 2)
        lo = cos_sun * np.sqrt(cos_s * cos_s * (1 - a2) + a2)
        li = cos_s * np.sqrt(cos_sun * cos_sun * (1 - a2) + a2)
        vis = 0.5 / np.maximum(lo + li, 1e-12)
        fresnel = GOLD + (1 - GOLD) * ((1 - i_h) ** 5)[:, None]
        f_cos = (d * vis * cos_sun)[:, None] * fresnel
        glossy.append(np.sum(f_cos * E_SUN * geo[:, None], 0).mean() * 0.5 / np.pi)
        lambert.append(np.sum((GOLD / np.pi) * cos_sun[:, None] * E_SUN * geo[:, None], 0).mean() * 0.5 / np.pi)
    return np.array(glossy), np.array(lambert)


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "/tmp/sbl"
    inst = load(f"{folder}/inst.exr")[..., 0]
    pixels = ground_pixels(inst)
    glossy, lambert = sphere_light([p for _, _, p in pixels])
    print(f"{len(pixels)} ground pixels; integrated, two bounces: glossy sphere {glossy.mean():.5f}, "
          f"Lambertian sphere {lambert.mean():.5f}, difference {(glossy - lambert).mean():.5f}")
    for name, a, b in [("reference, exactly two bounces", "r2_sun_boxes", "r2_lambert"),
                       ("reference, all bounces from two", "ref_sun_boxes", "ref_lambert"),
                       ("path GI", "m_sun_boxes", "m_lambert")]:
        ga, lb = load(f"{folder}/{a}.exr"), load(f"{folder}/{b}.exr")
        diff = np.mean([(ga[j, i] - lb[j, i]).mean() for j, i, _ in pixels])
        print(f"{name}: glossy minus Lambertian {diff:.5f}")


if __name__ == "__main__":
    main()
