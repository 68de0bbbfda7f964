#!/bin/bash
# usage: bash benches/results/gi_cold_2026-11-27/young_frames.sh FRAMES...
# From the repository root after `cargo build --release -p solari-app` (lavapipe here), it
# writes p_*.exr, A_*.exr and D_*.exr into the current directory and prints, per frame count,
# ReSTIR GI's mean ratio / relMSE against path GI at the same frame (raw frames): A with cold
# cells counted dark, D with them ignored (the adaptive cap at its default in both). The
# session's first probe compared more variants (the refresh of `experiments/`) the same way.
S=${S:-../shared/scenes/interior/interior.gltf}; B=${B:-target/release/solari}
SIZE=${SIZE:-160x90}; SCENE=${SCENE:-$S}
for f in "$@"; do
  $B render $SCENE --mode realtime --gi path --frames $f --size $SIZE --denoiser none --out p_$f.exr >/dev/null 2>&1
  line="f=$f"
  for v in A D; do
    case $v in A) a="--gi-ignore-cold-cells off";; D) a="--gi-ignore-cold-cells on";; esac
    $B render $SCENE --mode realtime --gi restir $a --frames $f --size $SIZE --denoiser none --out ${v}_$f.exr >/dev/null 2>&1
    r=$($B compare ${v}_$f.exr p_$f.exr --json | python3 -c 'import json,sys; d=json.load(sys.stdin)["all"]; print("%.3f/%.3f"%(d["mean_ratio"],d["rel_mse"]))')
    line="$line $v=$r"
  done
  echo "$line"
done
