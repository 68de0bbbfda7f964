#!/usr/bin/env bash
# Light toggles with the world cache's update rounds after each change (forty-first session),
# on the device (H200). Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT (`solari`: 67db0be).
# `solari soak SCENE --frames 4000 --toggle-lights 50 --size 1920x1080` (every pass's
# non-finite detector on, every frame; 80 light changes, each followed by 8 frames of four
# update rounds): interior and many_lights with the defaults, interior with
# `--gi restir --gi-half-rate`. Summaries: $OUT/soak_*.json.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
run() {
  local tag=$1 scene=$2; shift 2
  /root/bins/solari soak "$(scene_file "$scene")" --frames 4000 --toggle-lights 50 \
    --size 1920x1080 "$@" > "$OUT/soak_$tag.json" 2> "$OUT/soak_$tag.log"
  echo "$tag rc=$? $(tail -c 600 "$OUT/soak_$tag.json")"
}
run interior interior
run many_lights many_lights
run interior_restir_half interior --gi restir --gi-half-rate
