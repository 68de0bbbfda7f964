#!/usr/bin/env bash
# Internal resolution and the temporal upscaler on the H200 (device tool), one command.
# Issue 17, "Upscaling": 1080p output from 0.5 and 0.67 internal scale beside native 1080p
# (plain and antialiased), error against a 1080p reference and GPU time per frame.
# Direct light only on both sides (reference --max-bounces 1, real time --gi off), so the
# error measures resolution and filtering, not the GI that cache-only lighting lacks.
# Needs .gl, .dev/solari (stripped release build of the commit under test) and .dev/scenes
# carried. Usage: bash benches/results/upscale_h200.sh   (SCENES, SIZE, FRAMES, SPP override)
set -u
source benches/results/device_env.sh
BIN=${SOLARI_BIN:-.dev/solari}
R=${RESULTS:-/root/upscale}
SIZE=${SIZE:-1920x1080}
FRAMES=${FRAMES:-120}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
mkdir -p "$R"
for s in $SCENES; do
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  echo "== $s reference $(date -u +%T)" >&2
  "$BIN" render "$f" --mode reference --max-bounces 1 --spp "$SPP" --size "$SIZE" \
    --out "$R/${s}_ref.exr" --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  # (Antialiasing is on by default since the thirty-second session: named here.)
  for cfg in "1:off" "1:on" "0.67:auto" "0.5:auto"; do
    scale=${cfg%%:*}; aa=${cfg#*:}; extra="--antialias $aa"; name="${s}_${scale}"
    [ "$aa" = on ] && name="${name}_aa"
    echo "== $name $(date -u +%T)" >&2
    "$BIN" render "$f" --mode realtime --gi off --denoiser fallback --internal-scale "$scale" \
      $extra --frames "$FRAMES" --size "$SIZE" --json --out "$R/$name.exr" \
      > "$R/$name.json" 2> "$R/$name.log"
    "$BIN" compare "$R/$name.exr" "$R/${s}_ref.exr" --json > "$R/$name.compare.json" \
      2>> "$R/$name.log"
    rm -f "$R/$name.exr"
  done
  rm -f "$R/${s}_ref.exr"
done
mkdir -p "$OUT"
tar czf "$OUT/upscale_h200.tar.gz" -C "$R" .
for f in "$R"/*.compare.json; do
  n=$(basename "$f" .compare.json)
  python3 -c "import json,sys; c=json.load(open(sys.argv[1])); r=json.load(open(sys.argv[2])); a=c['all']; print(sys.argv[3], 'gpu_ms', r.get('gpu_frame_ms'), 'wall_ms', r.get('wall_frame_ms'), {k: a.get(k) for k in ('rmse','rel_mse','flip','flip_hdr')})" "$f" "$R/$n.json" "$n" 2>/dev/null || echo "$n: no figures"
done
