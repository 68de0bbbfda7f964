#!/usr/bin/env bash
# The lavapipe probes behind "Colour noise" (benches/RESULTS.md), on this workstation's CPU
# Vulkan (llvmpipe; 2 cores), with `cargo build --release -p solari-app` of the commit under
# test: the Cornell box at 128x128, the indirect view (`--view indirect --denoiser none`)
# against a `--min-bounces 2` reference of 2048 paths at pixel centres with its variance.
# Raw frame 136 of path GI with 1, 4 and 16 candidates and of ReSTIR GI with each spatial
# visibility and `--gi-shade-both off|on`; `split.py` prints each image's relMSE per channel
# (as `solari compare`), in luminance alone and in chroma alone. `mean` adds the mean of
# frames 137-200 of the ReSTIR variants (their convergence).
# Usage: bash benches/results/gi_colour_2026-11-29/lavapipe.sh [mean]   (pip install OpenEXR numpy)
set -u
S=${SOLARI:-target/release/solari}
C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf
W=${WORK:-/tmp/gi_colour_probes}; mkdir -p "$W"
here=$(dirname "$0")
[ -f "$W/ref.exr" ] || $S render $C --mode reference --min-bounces 2 --spp 2048 --pixel-centre \
  --size 128x128 --out "$W/ref.exr" --variance-out "$W/var.exr" > /dev/null
rt() { $S render $C --mode realtime --view indirect --denoiser none --size 128x128 "$@" > /dev/null; }
want_mean=${1:-}
images=()
for n in 1 4 16; do rt --gi path --gi-samples $n --frames 136 --out "$W/path$n.exr"; images+=("$W/path$n.exr"); done
for v in "chosen on" "both off" "both on" "neighbour off" "neighbour on"; do
  set -- $v
  rt --gi restir --gi-spatial-visibility $1 --gi-shade-both $2 --frames 136 --out "$W/restir_$1_$2.exr"
  images+=("$W/restir_$1_$2.exr")
  if [ "$want_mean" = mean ]; then
    rt --gi restir --gi-spatial-visibility $1 --gi-shade-both $2 --frames 200 --mean-of 64 --out "$W/restir_mean_$1_$2.exr"
    images+=("$W/restir_mean_$1_$2.exr")
  fi
done
python3 "$here/split.py" "$W/ref.exr" "$W/var.exr" "${images[@]}"
