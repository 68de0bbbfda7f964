#!/usr/bin/env bash
# Fallback denoiser frame by frame at 1920x1080 on the H200 (software BVH), as run through
# the device tool: carry [".gl", ".dev"], .dev/solari built with
# `cargo build --release -p solari-app`. Per scene: a 16384-path direct-only reference at
# pixel centres, then `bench-denoise` (static camera, 128 frames, à-trous iterations 1, 3, 5).
# Plots: cargo run -p solari-benches --bin plot-denoise -- denoise_frames_<scene>.csv OUT.png
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
mkdir -p /tmp/o
for s in cornell_box/cornell_box sun_boxes/sun_boxes many_lights/many_lights; do
  n=$(dirname $s)
  .dev/solari render .dev/scenes/$s.gltf --mode reference --max-bounces 1 --pixel-centre \
    --spp 16384 --size 1920x1080 --out /tmp/o/ref_$n.png --json >> /tmp/o/reference.jsonl 2>>/tmp/o/err.log
  .dev/solari bench-denoise .dev/scenes/$s.gltf --size 1920x1080 --frames 128 --iterations 1,3,5 \
    --reference /tmp/o/ref_$n.exr --csv /tmp/o/denoise_frames_$n.csv > /dev/null 2>>/tmp/o/err.log
  rm -f /tmp/o/ref_$n.exr /tmp/o/ref_$n.png
done
nvidia-smi --query-gpu=name,driver_version --format=csv > /tmp/o/gpu.txt
tar czf $OUT/denoise_frames.tgz -C /tmp/o .
