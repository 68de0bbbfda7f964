#!/bin/bash
# benches/RESULTS.md run: every shared scene and the heightfield, software backend.
S=.dev/solari
for sc in cornell_box/cornell_box.gltf sun_boxes/sun_boxes.gltf many_lights/many_lights.gltf \
          damaged_helmet/DamagedHelmet.gltf metal_rough_spheres/MetalRoughSpheresNoTextures.gltf; do
  $S bench-rays .dev/scenes/$sc --frames 200 --presets fastest,medium,very-slow --compare-checks --json
done
$S bench-rays --heightfield 2048 --frames 200 --presets fastest,medium,very-slow --compare-checks --json
