#!/bin/bash
S=.dev/solari
run() {
  local name=$1; shift
  local envs=(); while [ "$1" != "--" ]; do envs+=("$1"); shift; done; shift
  echo "=== $name" >> $OUT/exp2.log
  env "${envs[@]}" $S bench-rays "$@" --json 2>>$OUT/exp2.err >> $OUT/exp2.log
}
HF="--heightfield 2048 --frames 200"
run base X=1 -- $HF --presets fastest,medium --compare-checks
run tri SOLARI_EXP_FEATURES=exp_tri -- $HF --presets fastest,medium
run priv16 "SOLARI_EXP_PATCH=BVH_STACK_SIZE: u32 = 32u=>BVH_STACK_SIZE: u32 = 16u" -- $HF --presets fastest
run tri_priv16 SOLARI_EXP_FEATURES=exp_tri "SOLARI_EXP_PATCH=BVH_STACK_SIZE: u32 = 32u=>BVH_STACK_SIZE: u32 = 16u" -- $HF --presets fastest
for sc in many_lights/many_lights.gltf damaged_helmet/DamagedHelmet.gltf; do
  run base_$sc X=1 -- .dev/scenes/$sc --frames 200 --presets medium
  run tri_$sc SOLARI_EXP_FEATURES=exp_tri -- .dev/scenes/$sc --frames 200 --presets medium
done
