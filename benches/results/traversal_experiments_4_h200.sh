#!/bin/bash
S=.dev/solari
P='                in_blas = true;=>;;                in_blas = false;=>;;var in_blas = false=>let in_blas = true;;var node_group = vec2<u32>(package__1scene_bindings__1scene_info.tlas_root, 2147483648u)=>var node_group = vec2<u32>(package__1scene_bindings_instances[0].blas_root, 2147483648u)'
for v in base single; do
  if [ $v = single ]; then export SOLARI_EXP_PATCH="$P"; else unset SOLARI_EXP_PATCH; fi
  echo "=== $v" >> $OUT/exp4.log
  $S bench-rays --heightfield 2048 --frames 200 --presets fastest,very-slow --json 2>>$OUT/exp4.err >> $OUT/exp4.log
done
