#!/bin/bash
# World cache on the H200 (software BVH, 1920x1080). For the Cornell box and sun_boxes: a
# full-bounce reference (2048 paths at pixel centres), then bench-cache over cell sizes x
# update budgets against it (300 static frames per setting; timings and the error of the mean
# over frames 201-300, plus the error of frame 300 alone; a DI-only baseline row first), and a
# 240-frame real-time run with cache GI on an orbiting camera for the per-pass report. Then the
# cache view of the Cornell box.
S=.dev/solari
D=.dev/scenes
SIZE=1920x1080
for s in cornell_box/cornell_box sun_boxes/sun_boxes; do
  n=$(dirname $s)
  $S render $D/$s.gltf --mode reference --pixel-centre --spp 2048 --size $SIZE \
     --out $OUT/ref_$n.png --json >> $OUT/reference.jsonl 2>>$OUT/err.log
  $S bench-cache $D/$s.gltf --size $SIZE --frames 300 --warmup 200 \
     --cell-sizes 0.1,0.25,0.5,1.0 --budgets 5000,40000,1000000 --capacity 1048576 \
     --reference $OUT/ref_$n.exr --csv $OUT/sweep_$n.csv > /dev/null 2>>$OUT/err.log
  rm -f $OUT/ref_$n.exr
  $S render $D/$s.gltf --mode realtime --gi cache --frames 240 --camera-path orbit --size $SIZE \
     --out $OUT/realtime_$n.png --report $OUT/report_$n.jsonl --json >> $OUT/realtime.jsonl 2>>$OUT/err.log
  rm -f $OUT/realtime_$n.exr
done
$S render $D/cornell_box/cornell_box.gltf --mode realtime --view world-cache --frames 60 --size $SIZE \
   --out $OUT/view_cornell_box.png --json >> $OUT/realtime.jsonl 2>>$OUT/err.log
rm -f $OUT/view_cornell_box.exr
# Second command (same session): cost against live cells, far past the default cell size.
# for s in cornell_box sun_boxes; do
#   $S bench-cache $D/$s/$s.gltf --size $SIZE --frames 60 --warmup 30 \
#      --cell-sizes 0.01,0.02,0.05 --budgets 40000,1000000 --capacity 2097152 --csv $OUT/scale_$s.csv
# done
