#!/bin/bash
# Run against a build (not kept) whose single-instance traversal skipped the ray transform by
# a runtime branch on a scene-info flag (`if scene_info.first_instance_identity == 0u`) rather
# than the TRACE_UNTRANSFORMED pipeline constant; heightfield, H200, two repeats.
S=.dev/solari
for r in 1 2; do
  $S bench-rays --heightfield 2048 --frames 200 --presets fastest,medium,very-slow --json 2>>$OUT/hf.err >> $OUT/hf.jsonl
done
