#!/usr/bin/env bash
# A/B of two solari binaries on the device (H100/H200), interleaved on one warm machine:
# `solari render SCENE --mode realtime $FLAGS --frames $FRAMES --size 1920x1080 --json` with
# the base binary and the new one in turn, $REPS times per scene; then the traced G-buffer
# under each BVH build preset in $PRESETS with the new binary. Carry .gl, .dev/bins.tar.xz
# (stripped `solari` and `solari_base`) and .dev/SOLARI_COMMIT.
# Usage: bash benches/results/ab_passes_h200.sh  (SCENES, FLAGS, FRAMES, REPS, BVH_SCENES,
# PRESETS override; BINS names the binaries, default `solari_base solari`, for variants:
# the table then covers the default pair only, benches/results/memory_scratch_2026-11-26/
# ab_variants.py all of them). Results: $OUT/ab.tar.gz and $OUT/ab_table.txt
# (benches/results/ab_passes.py).
set -u
source benches/results/device_env.sh
unpack_bins
R=${RESULTS:-/root/ab}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
FLAGS=${FLAGS:---gi cache --denoiser fallback}
FRAMES=${FRAMES:-300}
REPS=${REPS:-2}
BVH_SCENES=${BVH_SCENES:-interior furnace_sphere metal_rough_spheres}
PRESETS=${PRESETS:-medium very-slow}
BINS=${BINS:-solari_base solari}
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
cp .dev/SOLARI_COMMIT "$R/" 2>/dev/null
# Warm-up: the first runs read 1.8-2x slow on the H100 (sweep_phases.sh), and with one
# warm-up run the first measured run still read 16% slow in its denoiser passes: one per
# binary, with the measured flags.
for b in $BINS; do
  /root/bins/$b render "$(scene_file cornell_box)" --mode realtime $FLAGS --frames 600 \
    --size 1920x1080 --out "$R/x.png" > /dev/null 2>&1
done
for rep in $(seq 1 "$REPS"); do
  # Alternate which binary runs first: with the base always first, the first scene of each
  # round read 4-9% faster with the new binary in every pass, unchanged ones included.
  order="$BINS"
  (( rep % 2 == 0 )) && order=$(echo $BINS | tr ' ' '\n' | tac | tr '\n' ' ')
  for s in $SCENES; do
    for b in $order; do
      echo "== $s $b rep $rep $(date -u +%T)" >&2
      /root/bins/$b render "$(scene_file "$s")" --mode realtime $FLAGS --frames "$FRAMES" \
        --size 1920x1080 --json --out "$R/x.png" > "$R/ab_${s}_${b}_${rep}.json" 2> "$R/ab_${s}_${b}_${rep}.log"
    done
  done
done
for s in $BVH_SCENES; do
  for p in $PRESETS; do
    echo "== $s bvh $p $(date -u +%T)" >&2
    /root/bins/solari render "$(scene_file "$s")" --mode realtime $FLAGS --gbuffer traced \
      --bvh-quality "$p" --frames "$FRAMES" --size 1920x1080 --json --out "$R/x.png" \
      > "$R/bvh_${s}_${p}.json" 2> "$R/bvh_${s}_${p}.log"
  done
done
rm -f "$R/x.png"
tar czf "$OUT/ab.tar.gz" -C "$R" .
python3 benches/results/ab_passes.py "$R" | tee "$OUT/ab_table.txt"
