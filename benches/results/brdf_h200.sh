#!/usr/bin/env bash
# Issue 19 item 5 on the H200 (device tool), one command: what the energy-conserving layered
# BRDF costs and how much light it gives back, against the binary before it (the seeds'
# layering) and the glTF specification's model.
#   1. timing, 1920x1080: `solari render --mode realtime --denoiser fallback --frames 200
#      --json` with the default settings, old and new binary interleaved per scene;
#   2. light, 960x540: the reference (`--mode reference --spp $SPP`) with the old binary, the
#      new one (`--brdf layered`, the default) and `--brdf gltf-spec`; the real-time image
#      (mean of 16 frames after 120) with old and new; then `solari compare` of each against
#      the new layered reference and of the old real-time image against the old reference
#      (mean/reference is the brightness ratio).
# Carry .gl and .dev: scenes, and bins.tar.xz holding solari (new) and solari_old (the build
# before the change), packed because the carry limit is 64 MiB.
# Usage: bash benches/results/brdf_h200.sh   (SCENES, SPP, PHASES override). The JSON and logs
# land in $OUT/brdf_h200.tar.gz; tables by benches/results/brdf_table.py.
set -u
source benches/results/device_env.sh
mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins
NEW=/root/bins/solari
OLD=/root/bins/solari_old
R=${RESULTS:-/root/brdf}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior metal_rough_spheres}
PHASES=${PHASES:-time light}
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
for s in $SCENES; do
  [[ " $PHASES " == *" time "* ]] || break
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  for round in 1 2; do
    for b in old new; do
      bin=$NEW; [ $b = old ] && bin=$OLD
      echo "== $s $b timing $round $(date -u +%T)" >&2
      "$bin" render "$f" --mode realtime --denoiser fallback --frames 200 --size 1920x1080 \
        --json --out "$R/x.png" > "$R/time_${s}_${b}_$round.json" 2> "$R/time_${s}_${b}_$round.log"
    done
  done
done
for s in $SCENES; do
  [[ " $PHASES " == *" light "* ]] || break
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  echo "== $s references $(date -u +%T)" >&2
  $OLD render "$f" --mode reference --spp "$SPP" --size 960x540 --out "$R/${s}_ref_old.exr" \
    --json > "$R/${s}_ref_old.json" 2> "$R/${s}_ref_old.log"
  for m in layered gltf-spec; do
    $NEW render "$f" --mode reference --brdf $m --spp "$SPP" --size 960x540 \
      --out "$R/${s}_ref_$m.exr" --json > "$R/${s}_ref_$m.json" 2> "$R/${s}_ref_$m.log"
  done
  echo "== $s real-time $(date -u +%T)" >&2
  for b in old new; do
    bin=$NEW; [ $b = old ] && bin=$OLD
    "$bin" render "$f" --mode realtime --denoiser fallback --frames 136 --mean-of 16 \
      --size 960x540 --json --out "$R/${s}_rt_$b.exr" > "$R/${s}_rt_$b.json" 2> "$R/${s}_rt_$b.log"
  done
  for t in ref_old ref_gltf-spec rt_new; do
    $NEW compare "$R/${s}_$t.exr" "$R/${s}_ref_layered.exr" --json \
      > "$R/cmp_${s}_${t}_vs_ref_layered.json" 2>&1
  done
  $NEW compare "$R/${s}_rt_old.exr" "$R/${s}_ref_old.exr" --json \
    > "$R/cmp_${s}_rt_old_vs_ref_old.json" 2>&1
done
echo "== done $(date -u +%T)" >&2
# The images stay behind (the device tool returns a few small files).
(cd "$R" && tar czf "$OUT/brdf_h200.tar.gz" *.json *.log gpu.csv)
