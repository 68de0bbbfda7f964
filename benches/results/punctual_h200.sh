#!/usr/bin/env bash
# Issue 19 item 1 on the H200 (device tool), one command: what point and spot lights cost.
#   1. regression, 1920x1080: `solari render --mode realtime --denoiser fallback --frames 200
#      --json` on scenes without point lights, the binary before point lights (solari_old),
#      the first one with them (solari_mid, if carried: every pass compiled with point-light
#      code) and the current one (solari: that code compiled out where a scene has none),
#      interleaved, two rounds;
#   2. interior_points (interior plus 32 lamps from point_scene.py: 24 point, 8 spot), same
#      timing: the old binary (lamps ignored), the new one with delta lamps
#      (--light-radius 0) and with spheres (--light-radius 0.05);
#   3. light, 960x540: the reference (--spp $SPP) and the real-time image (mean of 16 frames
#      after 120) of interior_points with spheres, then `solari compare` (mean/reference is
#      the brightness ratio).
# Carry .gl and .dev (scenes, bins.tar.xz with solari and solari_old; .dev/SOLARI_COMMIT
# names their commits). Usage: bash benches/results/punctual_h200.sh (SCENES, SPP override).
# JSON and logs land in $OUT/punctual_h200.tar.gz.
set -u
source benches/results/device_env.sh
mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins
NEW=/root/bins/solari
OLD=/root/bins/solari_old
MID=/root/bins/solari_mid
R=${RESULTS:-/root/punctual}
SPP=${SPP:-512}
SCENES=${SCENES:-cornell_box sun_boxes interior}
POINTS=.dev/scenes/interior/interior_points.gltf
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
time_run() { # name bin file extra...
  local name=$1 bin=$2 file=$3; shift 3
  echo "== $name $(date -u +%T)" >&2
  "$bin" render "$file" --mode realtime --denoiser fallback --frames 200 --size 1920x1080 \
    --json --out "$R/x.png" "$@" > "$R/time_$name.json" 2> "$R/time_$name.log"
}
for round in 1 2; do
  for s in $SCENES; do
    f=$(ls .dev/scenes/"$s"/"$s".gltf 2>/dev/null || ls .dev/scenes/"$s"/*.gltf | head -n 1)
    time_run "${s}_old_$round" $OLD "$f"
    [ -x $MID ] && time_run "${s}_mid_$round" $MID "$f"
    time_run "${s}_new_$round" $NEW "$f"
  done
  time_run "points_old_$round" $OLD $POINTS
  time_run "points_delta_$round" $NEW $POINTS --light-radius 0
  time_run "points_sphere_$round" $NEW $POINTS --light-radius 0.05
done
echo "== points reference $(date -u +%T)" >&2
$NEW render $POINTS --mode reference --light-radius 0.05 --spp "$SPP" --size 960x540 \
  --out "$R/points_ref.exr" --json > "$R/points_ref.json" 2> "$R/points_ref.log"
$NEW render $POINTS --mode realtime --light-radius 0.05 --denoiser fallback --frames 136 \
  --mean-of 16 --size 960x540 --json --out "$R/points_rt.exr" > "$R/points_rt.json" 2> "$R/points_rt.log"
$NEW compare "$R/points_rt.exr" "$R/points_ref.exr" --json > "$R/cmp_points_rt_vs_ref.json" 2>&1
$NEW render $POINTS --mode reference --light-radius 0.05 --spp 16 --size 960x540 \
  --out "$R/points_ref16.png" > /dev/null 2>&1
$NEW render $POINTS --mode realtime --light-radius 0.05 --denoiser fallback --frames 136 \
  --size 960x540 --out "$R/points_rt.png" > /dev/null 2>&1
cp "$R/points_ref16.png" "$R/points_rt.png" "$OUT/" 2>/dev/null
echo "== done $(date -u +%T)" >&2
(cd "$R" && tar czf "$OUT/punctual_h200.tar.gz" *.json *.log gpu.csv)
