#!/usr/bin/env bash
# Issue 19 item 4 (light grid) on the H200 (device tool), one command, on the generated field
# of 10,000 delta point lights (`--light-field 10000`) at 1920x1080:
#   1. the direct-only reference (`render --mode reference --max-bounces 1 --pixel-centre`,
#      --spp $SPP);
#   2. `solari bench-di` over initial candidates x light-grid share (off = light tiles
#      alone), 64 frames each of a static camera; the error columns average the squared
#      error of the last 16 frames against the reference;
#   3. whole-frame timing (`render --mode realtime --denoiser fallback --frames 200 --json`)
#      without and with `--light-grid`, interleaved, two rounds.
# Carry .gl and .dev (bins.tar.xz; .dev/SOLARI_COMMIT names the commit).
# Usage: bash benches/results/light_grid_h200.sh (SPP, CANDIDATES, SHARES override). CSV,
# JSON and logs land in $OUT/light_grid_h200.tar.gz.
set -u
source benches/results/device_env.sh
mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins
BIN=/root/bins/solari
R=${RESULTS:-/root/lgrid}
SPP=${SPP:-16384}
CANDIDATES=${CANDIDATES:-2,4,8,16,32}
SHARES=${SHARES:-off,0.5,0.75,0.9}
SCENE="--light-field 10000"
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
echo "== reference $(date -u +%T)" >&2
/usr/bin/time -v $BIN render $SCENE --mode reference --max-bounces 1 --pixel-centre \
  --spp "$SPP" --size 1920x1080 --out "$R/ref.exr" --json > "$R/ref.json" 2> "$R/ref.log"
echo "== sweep $(date -u +%T)" >&2
$BIN bench-di $SCENE --size 1920x1080 --frames 64 --warmup 8 --candidates "$CANDIDATES" --error-frames 16 \
  --light-grid "$SHARES" --reference "$R/ref.exr" --csv "$R/sweep.csv" > /dev/null \
  2> "$R/sweep.log"
for round in 1 2; do
  for g in off on; do
    echo "== frame grid $g $round $(date -u +%T)" >&2
    flag=""; [ $g = on ] && flag="--light-grid"
    $BIN render $SCENE --mode realtime --denoiser fallback --frames 200 --size 1920x1080 \
      $flag --json --out "$R/frame_$g.png" > "$R/frame_${g}_$round.json" \
      2> "$R/frame_${g}_$round.log"
  done
done
echo "== done $(date -u +%T)" >&2
(cd "$R" && tar czf "$OUT/light_grid_h200.tar.gz" *.json *.log *.csv gpu.csv frame_*.png)
