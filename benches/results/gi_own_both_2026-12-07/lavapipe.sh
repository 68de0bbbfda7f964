#!/usr/bin/env bash
# ReSTIR GI's own-reservoir share shaded over the temporal merge's choice
# (`--gi-own-both on`, `RestirGiSettings::own_share_both_samples`) against the one sample that
# merge kept (`off`), on this workstation's lavapipe (llvmpipe, 2 cores; `cargo build --release
# -p solari-app` of ebc7e80 with `own_both.patch` applied: the flag is not in the tree, see
# README). The references and their variance are
# ../cache_gi_2026-12-07/lavapipe.sh's (made there if absent: run it once first).
#   cornell (default): 128x128 indirect view raw (`--view indirect --denoiser none`), frame
#            136 and the mean of frames 137-200, by `split.py` (relMSE per channel, in
#            luminance alone and in chroma alone) and ../mean_brightness.py;
#   interior: 160x90, the same, frame 136 and the mean of frames 121-136;
#   lit:     the Cornell box's lit frame with the fallback denoiser at 128x128, frame 136 and
#            the mean of frames 121-136, by `solari compare --reference-variance` (relMSE
#            without the reference's noise, mean ratio).
# Usage: bash benches/results/gi_own_both_2026-12-07/lavapipe.sh [cornell|interior|lit]   (pip install OpenEXR numpy)
set -u
S=${SOLARI:-target/release/solari}
here=$(dirname "$0")
split=$here/../gi_colour_2026-11-29/split.py
case "${1:-cornell}" in
  cornell) C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf; size=128x128
           W=/tmp/gi_colour_probes; mean=(--frames 200 --mean-of 64) ;;
  interior) C=crates/solari-testdata/scenes/interior/interior.gltf; size=160x90
           W=/tmp/gi_interior_probes; mean=(--frames 136 --mean-of 16) ;;
  lit) C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf; W=/tmp/gi_lit_probes
       for v in off on; do
         for m in "136 1" "136 16"; do
           set -- $m
           $S render $C --mode realtime --denoiser fallback --size 128x128 --gi restir \
             --gi-own-both $v --frames $1 --mean-of $2 --out "$W/own_$v.exr" > /dev/null 2>&1
           echo -n "lit own-both $v frames $1 mean of $2: relMSE, mean ratio "
           $S compare "$W/own_$v.exr" "$W/ref.exr" --reference-variance "$W/var.exr" --json | python3 -c \
             'import json,sys; d=json.load(sys.stdin); print(d["reference_noise"]["all"]["rel_mse_excess"], d["all"]["mean_ratio"])'
         done
       done
       exit 0 ;;
  *) echo "usage: $0 [cornell|interior|lit]" >&2; exit 2 ;;
esac
[ -f "$W/ref.exr" ] || { echo "no reference in $W: run ../cache_gi_2026-12-07/lavapipe.sh ${1:-cornell} first" >&2; exit 1; }
rt() { $S render $C --mode realtime --view indirect --denoiser none --size $size "$@" > /dev/null; }
images=()
for v in off on; do
  rt --gi restir --gi-own-both $v --frames 136 --out "$W/own_$v.exr"; images+=("$W/own_$v.exr")
  rt --gi restir --gi-own-both $v "${mean[@]}" --out "$W/ownmean_$v.exr"; images+=("$W/ownmean_$v.exr")
done
python3 "$split" "$W/ref.exr" "$W/var.exr" "${images[@]}"
python3 "$here/../mean_brightness.py" "$W/ref.exr" "${images[@]}"
