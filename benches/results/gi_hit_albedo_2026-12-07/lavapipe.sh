#!/usr/bin/env bash
# The workstation-side checks behind this folder's README (lavapipe, 2 cores; `cargo build
# --release -p solari-app`; SOLARI_OLD = a build of c3d6c16, the base colour at the hit):
#   interior: `interior` at 64x36, the indirect view raw, mean of frames 121-136, against a
#             1024-path `--min-bounces 2` reference made here: mean/reference and relMSE
#             without the reference's noise (read 0.973 / 0.046 with the base colour, 0.996 /
#             0.041 with the directional albedo).
#   bits:     the Cornell box (Lambertian only), 8 frames of the indirect view with one
#             llvmpipe thread and the traced G-buffer: the two builds' EXRs must be identical.
# Usage: SOLARI_OLD=... bash benches/results/gi_hit_albedo_2026-12-07/lavapipe.sh interior|bits
set -eu
S=${SOLARI:-target/release/solari}
W=${WORK:-/tmp/gi_hit_albedo}; mkdir -p "$W"
case "${1:-}" in
  interior)
    I=crates/solari-testdata/scenes/interior/interior.gltf
    [ -f "$W/ref.exr" ] || $S render $I --mode reference --min-bounces 2 --spp 1024 --pixel-centre \
      --size 64x36 --out "$W/ref.exr" --variance-out "$W/var.exr" > /dev/null
    for b in "$SOLARI_OLD" "$S"; do
      $b render $I --mode realtime --view indirect --denoiser none --size 64x36 --frames 136 \
        --mean-of 16 --out "$W/mean.exr" > /dev/null 2>&1
      echo -n "$b: "
      $S compare "$W/mean.exr" "$W/ref.exr" --reference-variance "$W/var.exr" --json | python3 -c \
        'import json,sys; d=json.load(sys.stdin); print("mean/ref", d["all"]["mean_ratio"], "relMSE", d["reference_noise"]["all"]["rel_mse_excess"])'
    done ;;
  bits)
    C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf
    for b in "$SOLARI_OLD" "$S"; do
      LP_NUM_THREADS=1 $b render $C --mode realtime --gbuffer traced --size 64x64 --frames 8 \
        --view indirect --denoiser none --out "$W/bits_$(basename "$b").exr" > /dev/null 2>&1
    done
    cmp "$W/bits_$(basename "$SOLARI_OLD").exr" "$W/bits_$(basename "$S").exr" && echo identical ;;
  *) echo "usage: $0 interior|bits" >&2; exit 2 ;;
esac
