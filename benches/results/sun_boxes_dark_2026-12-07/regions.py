#!/usr/bin/env python3
"""Where sun_boxes' path-GI indirect light falls short of the reference (this folder's README).

Usage: regions.py REF.exr MASK_ON.exr MASK_OFF.exr SCALE IMAGE.exr [IMAGE.exr ...]

MASK_ON and MASK_OFF are the indirect view rendered at 1/SCALE of the images' size with
specular GI on and with `--specular-gi off`: pixels where the second keeps under a fifth of
the first's light are the gold sphere's (its indirect light is nearly all specular GI); the
mask is widened by one pixel of theirs. For each image: mean/reference over all pixels, over the sphere's, and over the
diffuse pixels near the sphere (image blocks rows 4-6, columns 4-8 of a 9x16 grid) and
elsewhere, then each block's share of the diffuse pixels' shortfall (per cent).
"""
import sys
import numpy as np
import OpenEXR


def load(path):
    ch = OpenEXR.File(path).channels()
    rgb = ch["RGB"].pixels if "RGB" in ch else np.stack([ch[c].pixels for c in "RGB"], -1)
    return rgb.astype(np.float64).mean(-1)


def main():
    ref, spec_on, spec_off = load(sys.argv[1]), load(sys.argv[2]), load(sys.argv[3])
    scale, images = int(sys.argv[4]), sys.argv[5:]
    sphere = (spec_off < 0.2 * spec_on) & (spec_on > 0)
    wide = sphere.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            wide |= np.roll(np.roll(sphere, dy, 0), dx, 1)
    mask = np.kron(wide.astype(np.uint8), np.ones((scale, scale), np.uint8)).astype(bool)
    h, w = ref.shape
    bh, bw = h // 9, w // 16
    near = np.zeros_like(mask)
    near[4 * bh:7 * bh, 4 * bw:9 * bw] = True
    near &= ~mask
    far = ~mask & ~near
    ratio = lambda m, k: m[k].sum() / ref[k].sum()
    print(f"reference shares: sphere {ref[mask].sum() / ref.sum():.3f}, "
          f"diffuse near it {ref[near].sum() / ref.sum():.3f}")
    for path in images:
        m = load(path)
        print(f"{path}: all {m.sum() / ref.sum():.4f}  sphere {ratio(m, mask):.4f}  "
              f"diffuse near {ratio(m, near):.4f}  diffuse elsewhere {ratio(m, far):.4f}")
    m = load(images[0])
    short = ref[~mask].sum() - m[~mask].sum()
    print(f"{images[0]}: share of the diffuse pixels' shortfall per block (%)")
    for y in range(9):
        row = []
        for x in range(16):
            s = (slice(y * bh, (y + 1) * bh), slice(x * bw, (x + 1) * bw))
            k = ~mask[s]
            row.append(f"{100 * (ref[s][k].sum() - m[s][k].sum()) / short:5.1f}")
        print(" ".join(row))


if __name__ == "__main__":
    main()
