#!/usr/bin/env bash
# Issue 19 item 3 (BRDF-sampled ReSTIR DI candidates) on the H200 (device tool), one command.
#   1. timing, 1920x1080: `solari render --mode realtime --denoiser fallback --frames 200
#      --json` with --brdf-candidates 0 and 1, interleaved, two rounds;
#   2. error of direct light, 960x540: the reference with --max-bounces 1 (--spp $SPP)
#      against real-time DI alone (--gi off --specular-gi off --denoiser none) with 0 and 1
#      BRDF candidates, one frame (the 64th) and the mean of 16 frames after 48.
# Scenes named NAME+sky load .dev/sky.hdr (benches/results/sky_hdr.py) as the environment.
# Carry .gl and .dev (scenes, sky.hdr, bins.tar.xz; .dev/SOLARI_COMMIT names the commit).
# Usage: bash benches/results/brdf_candidates_h200.sh (SCENES, SPP override). JSON and logs
# land in $OUT/brdf_candidates_h200.tar.gz.
set -u
source benches/results/device_env.sh
mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins
BIN=/root/bins/solari
R=${RESULTS:-/root/brdfc}
SPP=${SPP:-1024}
SCENES=${SCENES:-metal_rough_spheres sun_boxes+sky interior+sky emissive_strength_test}
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
args() { # scene name -> file and environment options
  local s=${1%+sky}
  echo "$(ls .dev/scenes/$s/*.gltf | head -n 1)"
  [ "$s" != "$1" ] && echo "--environment .dev/sky.hdr"
}
for round in 1 2; do
  for s in $SCENES; do
    for b in 0 1; do
      echo "== $s brdf $b timing $round $(date -u +%T)" >&2
      $BIN render $(args $s) --mode realtime --denoiser fallback --frames 200 --size 1920x1080 \
        --brdf-candidates $b --json --out "$R/x.png" > "$R/time_${s}_b${b}_$round.json" \
        2> "$R/time_${s}_b${b}_$round.log"
    done
  done
done
for s in $SCENES; do
  echo "== $s error $(date -u +%T)" >&2
  $BIN render $(args $s) --mode reference --max-bounces 1 --pixel-centre --spp "$SPP" \
    --size 960x540 --out "$R/${s}_ref.exr" --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  for b in 0 1; do
    for m in 1 16; do
      f=$((48 + m))
      $BIN render $(args $s) --mode realtime --gi off --specular-gi off --denoiser none \
        --frames $f --mean-of $m --brdf-candidates $b --size 960x540 --json \
        --out "$R/${s}_b${b}_m$m.exr" > "$R/${s}_b${b}_m$m.json" 2> "$R/${s}_b${b}_m$m.log"
      $BIN compare "$R/${s}_b${b}_m$m.exr" "$R/${s}_ref.exr" --json \
        > "$R/cmp_${s}_b${b}_m$m.json" 2>&1
    done
  done
done
echo "== done $(date -u +%T)" >&2
(cd "$R" && tar czf "$OUT/brdf_candidates_h200.tar.gz" *.json *.log gpu.csv)
