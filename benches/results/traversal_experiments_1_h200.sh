#!/bin/bash
# Traversal variants: runtime checks, stack size and placement. Logs under $OUT.
S=.dev/solari
run() { # name, env..., then args after --
  local name=$1; shift
  local envs=(); while [ "$1" != "--" ]; do envs+=("$1"); shift; done; shift
  echo "=== $name" | tee -a $OUT/exp1.log
  env "${envs[@]}" $S bench-rays "$@" --compare-trusted --json 2>>$OUT/exp1.err | tee -a $OUT/exp1.jsonl | tee -a $OUT/exp1.log
}
HF="--heightfield 2048 --frames 100 --presets fastest"
run base X=1 -- $HF
run chk_bounds SOLARI_EXP_CHECKS=bounds -- $HF
run chk_loops SOLARI_EXP_CHECKS=loops -- $HF
run priv16 "SOLARI_EXP_PATCH=BVH_STACK_SIZE: u32 = 32u=>BVH_STACK_SIZE: u32 = 16u" -- $HF
run shared8 SOLARI_EXP_FEATURES=shared_stack -- $HF
run shared4 SOLARI_EXP_FEATURES=shared_stack "SOLARI_EXP_PATCH=BVH_SHARED_ENTRIES: u32 = 8u=>BVH_SHARED_ENTRIES: u32 = 4u" -- $HF
run shared12 SOLARI_EXP_FEATURES=shared_stack "SOLARI_EXP_PATCH=BVH_SHARED_ENTRIES: u32 = 8u=>BVH_SHARED_ENTRIES: u32 = 12u" -- $HF
run shared16 SOLARI_EXP_FEATURES=shared_stack "SOLARI_EXP_PATCH=BVH_SHARED_ENTRIES: u32 = 8u=>BVH_SHARED_ENTRIES: u32 = 16u" -- $HF
for sc in many_lights/many_lights.gltf damaged_helmet/DamagedHelmet.gltf; do
  run base_$sc X=1 -- .dev/scenes/$sc --frames 200 --presets medium
  run shared8_$sc SOLARI_EXP_FEATURES=shared_stack -- .dev/scenes/$sc --frames 200 --presets medium
done
