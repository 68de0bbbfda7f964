#!/usr/bin/env bash
# Fallback denoiser cost at 1920x1080 on the H200 (software BVH), as run through the device
# tool: carry [".gl", ".dev"], .dev/solari built with `cargo build --release -p solari-app`.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
mkdir -p /tmp/o
for scene in cornell_box sun_boxes; do
  arg=.dev/scenes/cornell_box/cornell_box.gltf; [ "$scene" = sun_boxes ] && arg=.dev/scenes/sun_boxes/sun_boxes.gltf
  for d in none fallback; do
    .dev/solari render $arg --mode realtime --size 1920x1080 --frames 240 --camera-path orbit \
      --denoiser $d --out /tmp/o/${scene}_$d.png --report /tmp/o/${scene}_$d.jsonl --json \
      > /tmp/o/${scene}_$d.json 2> /tmp/o/${scene}_$d.log
  done
  for it in 1 3 5; do
    .dev/solari render $arg --mode realtime --size 1920x1080 --frames 120 --camera-path orbit \
      --denoiser fallback --denoise-iterations $it --out /tmp/o/${scene}_it$it.png --json \
      > /tmp/o/${scene}_it$it.json 2> /tmp/o/${scene}_it$it.log
  done
done
nvidia-smi --query-gpu=name --format=csv > /tmp/o/gpu.txt
rm -f /tmp/o/*.png /tmp/o/*.exr
tar czf $OUT/denoise.tgz -C /tmp/o .
