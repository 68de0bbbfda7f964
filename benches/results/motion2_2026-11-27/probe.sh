#!/usr/bin/env bash
# Thirty-fourth session, lavapipe: relMSE of frame FRAMES (default 8) of the orbit camera at
# 320x180 against a 256-spp full-bounce reference of that frame, for one binary and flags.
# References first (once per scene and frame; interior takes about five minutes):
#   solari render crates/solari-testdata/scenes/$s/$s.gltf --mode reference --camera-path orbit \
#     --frames $FRAMES --spp 256 --size 320x180 --out $DIR/ref_${s}_$FRAMES.exr
# Usage: DIR=/tmp/orb3 FRAMES=8 bash probe.sh NAME BINARY SCENE [realtime flags]
#   e.g. ... probe.sh h50 target/release/solari interior --internal-scale 0.5
# (The per-pixel breakdowns in RESULTS.md came from a throwaway tool summing the same relMSE
# per pixel; `solari compare` gives the totals.)
set -u
name=$1; bin=$2; s=$3; shift 3
D=${DIR:-/tmp/orb3}; F=${FRAMES:-8}
f=$(ls crates/solari-testdata/scenes/$s/*.gltf | head -1)
"$bin" render "$f" --mode realtime --camera-path orbit --denoiser fallback --frames "$F" \
  --size 320x180 "$@" --out "$D/${name}_${s}_$F.exr" > "$D/${name}_${s}_$F.log" 2>&1
"$bin" compare "$D/${name}_${s}_$F.exr" "$D/ref_${s}_$F.exr" --json \
  | python3 -c "import json,sys; a=json.load(sys.stdin)['all']; print('$name $s frame $F relMSE %.5f'%a['rel_mse'])"
