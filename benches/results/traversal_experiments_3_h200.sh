#!/bin/bash
S=.dev/solari
P='let scale_idir = scale * idir=>let idir2 = package_trace__1safe_inverse(d); let scale_idir = scale * idir2;;let shifted_origin = (p - o) * idir=>let shifted_origin = (p - o) * idir2'
for v in base noidir; do
  if [ $v = noidir ]; then export SOLARI_EXP_PATCH="$P"; else unset SOLARI_EXP_PATCH; fi
  echo "=== $v" >> $OUT/exp3.log
  $S bench-rays --heightfield 2048 --frames 200 --presets fastest,very-slow --json 2>>$OUT/exp3.err >> $OUT/exp3.log
  for sc in many_lights/many_lights.gltf damaged_helmet/DamagedHelmet.gltf; do
    $S bench-rays .dev/scenes/$sc --frames 200 --presets medium --json 2>>$OUT/exp3.err >> $OUT/exp3.log
  done
done
