#!/usr/bin/env bash
# Does switching lights grow process memory? 10,000 frames at 1920x1080 (orbit camera, cache
# GI, fallback denoiser, detector on) with lights switched every 10 frames (999 switches) and
# every 1,000 (9), on metal_rough_spheres and many_lights; prints RSS after frame 100 and at
# the end, the loop's time per frame, submit's and the GPU's. Device command (nvidia-h200),
# carrying .gl and .dev (.dev/solari: a stripped release build; .dev/scenes: ../shared/scenes):
#   bash benches/results/soak_toggle_rss_h200.sh
# Summaries land in $OUT (committed: benches/results/soak_h200/toggle_rss_2026-11-23/).
set -u
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
S=.dev/scenes
for sc in metal_rough_spheres many_lights; do
  g=$(ls $S/$sc/*.gltf | head -n 1)
  for t in 10 1000; do
    .dev/solari soak "$g" --frames 10000 --size 1920x1080 --camera-path orbit --gi cache \
      --denoiser fallback --toggle-lights $t --progress-every 0 \
      --summary "$OUT/$sc-t$t.json" > /dev/null 2> "$OUT/$sc-t$t.log"
    python3 -c "
import json; d=json.load(open('$OUT/$sc-t$t.json')); r=d['process_rss_bytes']
print('$sc', $t, d['toggles'], 'rss', r['after_warmup'], r['end'], (r['end']-r['after_warmup'])/1e6,
      'MB loop', round(d['loop_ms_per_frame'],3), 'submit p50', round(d['wall_frame_ms']['p50'],3),
      'gpu p50', round(d['gpu_frame_ms']['p50'],3), 'clean', d['clean'])"
  done
done
