#!/usr/bin/env bash
# sun_boxes' path-GI indirect light against a full-bounce reference, on this workstation's
# lavapipe (2 cores), as in this folder's README.
#   SCENE (sun_boxes), SIZE (e.g. 320x180), SPP (reference paths per pixel, 256),
#   BINS: names of binaries /tmp/solari_NAME, each built from 40166cd with one patch of this
#         folder applied (base: none): `git apply P && cargo build --release -p solari-app &&
#         cp target/release/solari /tmp/solari_NAME && git checkout .` (for
#         glossy_hit_oracle.patch, set ORACLE_MODE_VALUE in the patched shader to 1u, 2u or 3u
#         before building: `sed -i s/ORACLE_MODE_VALUE/3u/ crates/solari-restir/shaders/restir_gi_initial.wesl`);
#   FLAGS: extra `solari render` flags for every binary;
#   WORK: where the images go (/tmp/sun_boxes_dark).
# Each: the indirect view raw (`--denoiser none`), mean of frames 121-136, against the
# reference (`--min-bounces 2 --pixel-centre`), printing mean/reference and relMSE without
# the reference's noise.
set -u
SCENE=${SCENE:-sun_boxes}; SIZE=${SIZE:-320x180}; SPP=${SPP:-256}; BINS=${BINS:-base}
W=${WORK:-/tmp/sun_boxes_dark}; mkdir -p "$W"
I=crates/solari-testdata/scenes/$SCENE/$SCENE.gltf
R=$W/ref_${SCENE}_${SIZE}_$SPP.exr; V=$W/var_${SCENE}_${SIZE}_$SPP.exr
S=/tmp/solari_base
[ -f "$R" ] || $S render "$I" --mode reference --min-bounces 2 --spp "$SPP" --pixel-centre \
  --size "$SIZE" --out "$R" --variance-out "$V" > /dev/null
for b in $BINS; do
  out=$W/${SCENE}_${SIZE}_$b$(printf '%s' "${FLAGS:-}" | tr -c 'a-z0-9.' '_').exr
  # shellcheck disable=SC2086
  /tmp/solari_$b render "$I" --mode realtime --view indirect --denoiser none --size "$SIZE" \
    --frames 136 --mean-of 16 ${FLAGS:-} --out "$out" > /dev/null 2>&1 || { echo "$b: failed"; continue; }
  echo -n "$SCENE $SIZE $b ${FLAGS:-}: "
  $S compare "$out" "$R" --reference-variance "$V" --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print("mean/ref %.4f relMSE %.4f" % (d["all"]["mean_ratio"], d["reference_noise"]["all"]["rel_mse_excess"]))'
done
