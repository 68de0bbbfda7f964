#!/usr/bin/env bash
# The lavapipe probes behind "Colour noise" (benches/RESULTS.md), on this workstation's CPU
# Vulkan (llvmpipe; 2 cores), with `cargo build --release -p solari-app` of the commit under
# test: the Cornell box at 128x128, the indirect view (`--view indirect --denoiser none`)
# against a `--min-bounces 2` reference of 2048 paths at pixel centres with its variance.
# Raw frame 136 of path GI with 1, 4 and 16 candidates and of ReSTIR GI with each spatial
# visibility and `--gi-shade-both off|on` (the own reservoir's share 0), and the one-ray
# default with its share of 0.5; `split.py` prints each image's relMSE per channel
# (as `solari compare`), in luminance alone and in chroma alone. `mean` adds the mean of
# frames 137-200 of the ReSTIR variants (their convergence); `sweep` instead renders the
# one-ray default at own-reservoir shares 0, 0.3, 0.5, 0.7, 0.85 and 1.
# Usage: bash benches/results/gi_colour_2026-11-29/lavapipe.sh [mean|sweep]   (pip install OpenEXR numpy)
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
if [ "$want_mean" = sweep ]; then
  for a in 0 0.3 0.5 0.7 0.85 1; do
    rt --gi restir --gi-own-share $a --frames 136 --out "$W/share_$a.exr"; images+=("$W/share_$a.exr")
  done
  python3 "$here/split.py" "$W/ref.exr" "$W/var.exr" "${images[@]}"
  exit
fi
for n in 1 4 16; do rt --gi path --gi-samples $n --frames 136 --out "$W/path$n.exr"; images+=("$W/path$n.exr"); done
# (spatial visibility, both samples shaded, the own reservoir's share)
for v in "chosen on 0" "chosen on 0.5" "both off 0" "both on 0" "neighbour off 0" "neighbour on 0"; do
  set -- $v
  f="restir_$1_$2_$3"
  rt --gi restir --gi-spatial-visibility $1 --gi-shade-both $2 --gi-own-share $3 --frames 136 --out "$W/$f.exr"
  images+=("$W/$f.exr")
  if [ "$want_mean" = mean ]; then
    rt --gi restir --gi-spatial-visibility $1 --gi-shade-both $2 --gi-own-share $3 --frames 200 --mean-of 64 --out "$W/mean_$f.exr"
    images+=("$W/mean_$f.exr")
  fi
done
python3 "$here/split.py" "$W/ref.exr" "$W/var.exr" "${images[@]}"
