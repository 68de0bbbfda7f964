#!/bin/bash
# Reference path tracer throughput and light-selection error, as recorded in benches/RESULTS.md.
# Usage: benches/reference_h200.sh SOLARI_BINARY SCENES_DIR OUT_DIR
S=$1; SC=$2; OUT=$3
mkdir -p $OUT
for sc in cornell_box/cornell_box.gltf furnace_uniform/furnace_uniform.gltf furnace_sphere/furnace_sphere.gltf \
          sun_boxes/sun_boxes.gltf many_lights/many_lights.gltf emissive_strength_test/EmissiveStrengthTest.gltf \
          damaged_helmet/DamagedHelmet.gltf metal_rough_spheres/MetalRoughSpheresNoTextures.gltf; do
  n=$(basename $sc .gltf)
  $S render $SC/$sc --mode reference --size 1920x1080 --spp 256 --json --out $OUT/$n.png >> $OUT/reference_throughput.jsonl
done
# Uniform against power-proportional light selection at equal samples (16 spp, 512x512),
# against a 4096-spp power-selection render of the same scene.
for sc in many_lights/many_lights.gltf sun_boxes/sun_boxes.gltf emissive_strength_test/EmissiveStrengthTest.gltf; do
  n=$(basename $sc .gltf)
  $S render $SC/$sc --mode reference --size 512x512 --spp 4096 --json --out $OUT/${n}_truth.png >> $OUT/selection_renders.jsonl
  for sel in uniform power; do
    $S render $SC/$sc --mode reference --size 512x512 --spp 16 --selection $sel --json --out $OUT/${n}_$sel.png >> $OUT/selection_renders.jsonl
    echo "{\"scene\":\"$n\",\"selection\":\"$sel\",\"metrics\":$($S compare $OUT/${n}_$sel.exr $OUT/${n}_truth.exr --mask-emitters $SC/$sc --json)}" >> $OUT/selection_error.jsonl
  done
done
