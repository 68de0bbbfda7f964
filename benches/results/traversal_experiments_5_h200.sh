#!/bin/bash
# Which part of the single-instance specialisation costs the last 4% (heightfield, H200).
S=.dev/solari
T='    if package_trace__2TRACE_SINGLE_INSTANCE {
        let inst = package__1scene_bindings_instances[0];
        o = package__1scene_types__1xform_point(inst.world_to_object, origin);
        d = package__1scene_types__1xform_dir(inst.world_to_object, direction);'
T2='    if package_trace__2TRACE_SINGLE_INSTANCE {
        let inst = package__1scene_bindings_instances[0];'
NOXF="$T=>$T2"
SC='if package_trace__2TRACE_SINGLE_INSTANCE || in_blas {=>if in_blas {;;if !package_trace__2TRACE_SINGLE_INSTANCE && in_blas && sp == blas_base {=>if false {'
EXP4='                in_blas = true;=>;;                in_blas = false;=>;;var in_blas = false=>let in_blas = true;;var node_group = vec2<u32>(package__1scene_bindings__1scene_info.tlas_root, 2147483648u)=>var node_group = vec2<u32>(package__1scene_bindings_instances[0].blas_root, 2147483648u);;        in_blas = true;=>'
for v in base noxf sc noxf_sc exp4; do
  case $v in
    base) unset SOLARI_EXP_PATCH;;
    noxf) export SOLARI_EXP_PATCH="$NOXF";;
    sc) export SOLARI_EXP_PATCH="$SC";;
    noxf_sc) export SOLARI_EXP_PATCH="$SC;;$NOXF";;
    exp4) export SOLARI_EXP_PATCH="$EXP4";;
  esac
  echo "=== $v" >> $OUT/exp6.log
  $S bench-rays --heightfield 2048 --frames 200 --presets fastest,very-slow --json 2>>$OUT/exp6.err >> $OUT/exp6.log
done
