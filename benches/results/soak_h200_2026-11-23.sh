#!/usr/bin/env bash
# Soak runs of the whole real-time pipeline on the H200 (device tool), one summary per run
# appended to $OUT/soak.jsonl and the progress lines to $OUT/soak.log.
#
# Needs, carried in the working tree: .gl/ (Vulkan loader packages, see the device README),
# .dev/solari (a release build of this commit, stripped) and .dev/scenes (a copy of
# ../shared/scenes). Usage (in the device command):
#   FRAMES=100000 TOGGLE=1000 SCENES="cornell_box sun_boxes" bash benches/results/soak_h200.sh
# FRAMES defaults to 100000; TOGGLE empty runs with static lights; SCENES defaults to every
# shared scene. Settings: 1920x1080, orbit camera, cache GI, fallback denoiser, software BVH
# (the H200 has no ray queries), the non-finite detector on every pass of every frame.
set -u
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
FRAMES=${FRAMES:-100000}
TOGGLE=${TOGGLE:-}
SCENES=${SCENES:-"cornell_box damaged_helmet emissive_strength_test furnace_sphere furnace_uniform interior many_lights metal_rough_spheres sun_boxes"}
OUT=${OUT:-/tmp/soak-out}
mkdir -p "$OUT"
for s in $SCENES; do
  file=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  toggle=()
  [ -n "$TOGGLE" ] && toggle=(--toggle-lights "$TOGGLE")
  echo "== $s frames=$FRAMES toggle=${TOGGLE:-none} $(date -u +%T)" >> "$OUT/soak.log"
  .dev/solari soak "$file" --frames "$FRAMES" --size 1920x1080 --camera-path orbit \
      --gi cache --denoiser fallback "${toggle[@]}" --progress-every 10000 \
      --summary "$OUT/summary.json" 2>> "$OUT/soak.log" > /dev/null
  echo "exit $? $(date -u +%T)" >> "$OUT/soak.log"
  if [ -f "$OUT/summary.json" ]; then
    python3 -c "import json,sys; print(json.dumps(json.load(open(sys.argv[1]))))" \
        "$OUT/summary.json" >> "$OUT/soak.jsonl"
    rm -f "$OUT/summary.json"
  fi
done
