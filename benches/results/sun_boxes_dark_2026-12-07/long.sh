#!/usr/bin/env bash
# The 1,024-frame means of the README's section 2 (lavapipe, sun_boxes at 320x180, path GI's
# raw indirect light): /tmp/solari_base (40166cd, lifetime 30) and /tmp/solari_or3 (40166cd
# with `glossy_hit_oracle.patch`, ORACLE_MODE_VALUE set to 3u) over frames 137-1160, each
# against the reference that `lavapipe.sh` makes at 320x180 (REF, VAR), then `regions.py`
# with the mask pair MASK_ON / MASK_OFF (320x180 renders with and without `--specular-gi off`).
# Building the oracle: git apply glossy_hit_oracle.patch && sed -i s/ORACLE_MODE_VALUE/3u/
#   crates/solari-restir/shaders/restir_gi_initial.wesl && cargo build --release -p solari-app
# Usage: REF=... VAR=... MASK_ON=... MASK_OFF=... bash long.sh [OUT_DIR]
set -eu
OUT=${1:-/tmp/sb}
HERE=$(cd "$(dirname "$0")" && pwd)
I=crates/solari-testdata/scenes/sun_boxes/sun_boxes.gltf
for b in base or3; do
  /tmp/solari_$b render "$I" --mode realtime --view indirect --denoiser none --size 320x180 \
    --frames 1160 --mean-of 1024 --out "$OUT/late_$b.exr" > /dev/null
  echo -n "$b: "
  /tmp/solari_base compare "$OUT/late_$b.exr" "$REF" --reference-variance "$VAR" --json | python3 -c \
    'import json,sys; d=json.load(sys.stdin); print("mean/ref %.4f relMSE %.6f" % (d["all"]["mean_ratio"], d["reference_noise"]["all"]["rel_mse_excess"]))'
done
python3 "$HERE/regions.py" "$REF" "$MASK_ON" "$MASK_OFF" 1 "$OUT/late_base.exr" "$OUT/late_or3.exr" | sed -n 1,3p
