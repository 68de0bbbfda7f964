#!/usr/bin/env bash
# Cache GI beside path and ReSTIR GI on GI's own error, on this workstation's lavapipe
# (llvmpipe, 2 cores; `cargo build --release -p solari-app`): the indirect view raw
# (`--view indirect --denoiser none`) against a `--min-bounces 2` reference at pixel centres
# (made here if absent), with `split.py`'s relMSE per channel, in luminance and in chroma
# alone, and each image's mean brightness against the reference's (../mean_brightness.py).
#   cornell (default): 128x128, reference of 2048 paths (shared with
#            ../gi_history_2026-11-29/lavapipe.sh), frame 136 and the mean of frames 137-200;
#   interior: 160x90, reference of 1024 paths (about 9 minutes here), frame 136 and the mean
#            of frames 121-136;
#   lit:     the Cornell box's lit frame with the fallback denoiser (frame 136 and the mean of
#            frames 121-136) against a 2048-path full-bounce reference at 128x128, by `solari
#            compare --reference-variance`: relMSE without the reference's noise, mean ratio.
# Usage: bash benches/results/cache_gi_2026-12-07/lavapipe.sh [cornell|interior|lit]   (pip install OpenEXR numpy)
set -u
S=${SOLARI:-target/release/solari}
if [ "${1:-}" = lit ]; then
  C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf
  W=${WORK:-/tmp/gi_lit_probes}; mkdir -p "$W"
  [ -f "$W/ref.exr" ] || $S render $C --mode reference --spp 2048 --size 128x128 --out "$W/ref.exr" \
    --variance-out "$W/var.exr" > /dev/null
  for g in cache path restir; do
    $S render $C --mode realtime --denoiser fallback --size 128x128 --gi $g --frames 136 \
      --out "$W/l_$g.exr" > /dev/null 2>&1
    $S render $C --mode realtime --denoiser fallback --size 128x128 --gi $g --frames 136 \
      --mean-of 16 --out "$W/lm_$g.exr" > /dev/null 2>&1
    for f in l lm; do
      echo -n "$f $g "
      $S compare "$W/${f}_$g.exr" "$W/ref.exr" --reference-variance "$W/var.exr" --json | python3 -c \
        'import json,sys; d=json.load(sys.stdin); print(d["reference_noise"]["all"]["rel_mse_excess"], d["all"]["mean_ratio"])'
    done
  done
  exit 0
fi
case "${1:-cornell}" in
  cornell) C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf; size=128x128; spp=2048
           W=${WORK:-/tmp/gi_colour_probes}; mean=(--frames 200 --mean-of 64) ;;
  interior) C=crates/solari-testdata/scenes/interior/interior.gltf; size=160x90; spp=1024
           W=${WORK:-/tmp/gi_interior_probes}; mean=(--frames 136 --mean-of 16) ;;
  *) echo "usage: $0 [cornell|interior|lit]" >&2; exit 2 ;;
esac
mkdir -p "$W"
[ -f "$W/ref.exr" ] || $S render $C --mode reference --min-bounces 2 --spp $spp --pixel-centre \
  --size $size --out "$W/ref.exr" --variance-out "$W/var.exr" > /dev/null
imgs=()
for g in cache path restir; do
  $S render $C --mode realtime --view indirect --denoiser none --size $size --gi $g \
    --frames 136 --out "$W/g_$g.exr" > "$W/g_$g.log" 2>&1
  $S render $C --mode realtime --view indirect --denoiser none --size $size --gi $g \
    "${mean[@]}" --out "$W/gm_$g.exr" > /dev/null 2>&1
  imgs+=("$W/g_$g.exr" "$W/gm_$g.exr")
done
python3 "$(dirname "$0")/../gi_colour_2026-11-29/split.py" "$W/ref.exr" "$W/var.exr" "${imgs[@]}"
python3 "$(dirname "$0")/../mean_brightness.py" "$W/ref.exr" "${imgs[@]}"
