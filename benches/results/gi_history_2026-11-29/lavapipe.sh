#!/usr/bin/env bash
# The lavapipe probes behind "The spatial merge as history" (benches/RESULTS.md), on this
# workstation's CPU Vulkan (llvmpipe; 2 cores), with `cargo build --release -p solari-app`:
# the Cornell box at 128x128, the indirect view (`--view indirect --denoiser none`, ReSTIR GI
# with its defaults but the flags named) against the `--min-bounces 2` reference of 2048
# paths at pixel centres that `../gi_colour_2026-11-29/lavapipe.sh` renders (made here if
# absent); raw frame 136 and the mean of frames 137-200 of each variant. `split.py` prints
# each image's relMSE per channel, in luminance alone and in chroma alone; the last lines
# give each mean's brightness against the reference's.
# Usage: bash benches/results/gi_history_2026-11-29/lavapipe.sh   (pip install OpenEXR numpy)
set -u
S=${SOLARI:-target/release/solari}
C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf
W=${WORK:-/tmp/gi_colour_probes}; mkdir -p "$W"
[ -f "$W/ref.exr" ] || $S render $C --mode reference --min-bounces 2 --spp 2048 --pixel-centre \
  --size 128x128 --out "$W/ref.exr" --variance-out "$W/var.exr" > /dev/null
imgs=()
v() { local n=$1; shift
  $S render $C --mode realtime --view indirect --denoiser none --size 128x128 --gi restir "$@" \
    --frames 136 --out "$W/h_$n.exr" > /dev/null
  $S render $C --mode realtime --view indirect --denoiser none --size 128x128 --gi restir "$@" \
    --frames 200 --mean-of 64 --out "$W/hm_$n.exr" > /dev/null
  imgs+=("$W/h_$n.exr" "$W/hm_$n.exr")
}
v defaults
v own --gi-spatial-history off
v own_share0 --gi-spatial-history off --gi-own-share 0
v own_cap16 --gi-spatial-history off --gi-confidence-cap 16
v own_cap32 --gi-spatial-history off --gi-confidence-cap 32
v own_both --gi-spatial-history off --gi-spatial-visibility both
v own_both_cap16 --gi-spatial-history off --gi-confidence-cap 16 --gi-spatial-visibility both
v own_cap4 --gi-spatial-history off --gi-confidence-cap 4
for c in 4 16 32; do v cap$c --gi-confidence-cap $c; done
python3 "$(dirname "$0")/../gi_colour_2026-11-29/split.py" "$W/ref.exr" "$W/var.exr" "${imgs[@]}"
means=(); for f in "${imgs[@]}"; do case $f in */hm_*) means+=("$f") ;; esac; done
python3 "$(dirname "$0")/../mean_brightness.py" "$W/ref.exr" "${means[@]}"
