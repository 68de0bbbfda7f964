#!/bin/bash
# ReSTIR DI on the H200 (software BVH, 1920x1080): for each shared scene with lights, a
# direct-only reference (4096 paths at pixel centres), the candidates x light-tiles sweep
# against it (40 static frames per setting, 8 untimed), and a 120-frame real-time run with the
# default settings on an orbiting camera for the per-pass report. Scenes without lights get
# the real-time run only (it shows the skipped passes).
S=.dev/solari
D=.dev/scenes
SIZE=1920x1080
for s in cornell_box/cornell_box many_lights/many_lights sun_boxes/sun_boxes \
         emissive_strength_test/EmissiveStrengthTest; do
  n=$(dirname $s)
  $S render $D/$s.gltf --mode reference --max-bounces 1 --pixel-centre --spp 4096 --size $SIZE \
     --out $OUT/ref_$n.png --json >> $OUT/reference.jsonl 2>>$OUT/err.log
  $S bench-di $D/$s.gltf --size $SIZE --frames 40 --warmup 8 --candidates 1,2,4,8,16,32 \
     --tiles 32x256,128x1024,256x4096 --reference $OUT/ref_$n.exr --csv $OUT/sweep_$n.csv \
     > /dev/null 2>>$OUT/err.log
  rm -f $OUT/ref_$n.exr
done
for s in cornell_box/cornell_box many_lights/many_lights sun_boxes/sun_boxes \
         emissive_strength_test/EmissiveStrengthTest damaged_helmet/DamagedHelmet \
         metal_rough_spheres/MetalRoughSpheresNoTextures; do
  n=$(dirname $s)
  $S render $D/$s.gltf --mode realtime --frames 120 --camera-path orbit --size $SIZE \
     --out $OUT/realtime_$n.png --report $OUT/report_$n.jsonl --json >> $OUT/realtime.jsonl 2>>$OUT/err.log
  rm -f $OUT/realtime_$n.exr
done
