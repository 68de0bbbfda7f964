#!/usr/bin/env bash
# The renders behind this folder's README, section 2 (lavapipe, 320x180), into DIR (default
# /tmp/sbl): the variants of `make.py`; for each of sun_boxes, lambert and lifted a 256-path
# `--min-bounces 2` reference and path GI's raw indirect light (mean of frames 121-136) from
# /tmp/solari_life1000 (40166cd with `lifetime_1000.patch`), printing mean / reference over all
# pixels, the blocks near the sphere (rows 4-6, columns 4-8 of 9x16) and the rest; then the
# inputs of `../caustic.py` (the instance view, and 2048-path references of exactly two
# bounces for sun_boxes and lambert) and its output. /tmp/solari_base is 40166cd.
# Usage: bash variants/run.sh [DIR]   (from the repository root)
set -eu
DIR=${1:-/tmp/sbl}
HERE=$(cd "$(dirname "$0")" && pwd)
python3 "$HERE/make.py" "$DIR"
for v in sun_boxes lambert lifted; do
  /tmp/solari_base render "$DIR/$v.gltf" --mode reference --min-bounces 2 --spp 256 --pixel-centre \
    --size 320x180 --out "$DIR/ref_$v.exr" --variance-out "$DIR/var_$v.exr" > /dev/null
  /tmp/solari_life1000 render "$DIR/$v.gltf" --mode realtime --view indirect --denoiser none \
    --size 320x180 --frames 136 --mean-of 16 --out "$DIR/m_$v.exr" > /dev/null
  python3 - "$DIR" "$v" <<'P'
import sys
import numpy as np
import OpenEXR
d, v = sys.argv[1], sys.argv[2]
def load(p):
    ch = OpenEXR.File(p).channels()
    rgb = ch["RGB"].pixels if "RGB" in ch else np.stack([ch[c].pixels for c in "RGB"], -1)
    return rgb.astype(np.float64).mean(-1)
r, m = load(f"{d}/ref_{v}.exr"), load(f"{d}/m_{v}.exr")
h, w = r.shape
near = np.zeros(r.shape, bool)
near[4 * (h // 9):7 * (h // 9), 4 * (w // 16):9 * (w // 16)] = True
print(f"{v}: all {m.sum() / r.sum():.4f}  near the sphere {m[near].sum() / r[near].sum():.4f}  "
      f"elsewhere {m[~near].sum() / r[~near].sum():.4f}")
P
done
/tmp/solari_base render "$DIR/sun_boxes.gltf" --view instance --size 320x180 --out "$DIR/inst.exr" > /dev/null
for v in sun_boxes lambert; do
  /tmp/solari_base render "$DIR/$v.gltf" --mode reference --min-bounces 2 --max-bounces 2 --spp 2048 \
    --pixel-centre --size 320x180 --out "$DIR/r2_$v.exr" --variance-out "$DIR/v2_$v.exr" > /dev/null
done
python3 "$HERE/../caustic.py" "$DIR"
