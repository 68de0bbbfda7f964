#!/bin/bash
# Heightfield with the untransformed single-instance variant (H200): --compare-checks also runs
# single-instance and two-level for the same BVH; very-slow twice.
S=.dev/solari
$S bench-rays --heightfield 2048 --frames 200 --presets fastest,medium,very-slow --compare-checks --json 2>>$OUT/hf.err >> $OUT/hf.jsonl
$S bench-rays --heightfield 2048 --frames 200 --presets very-slow --json 2>>$OUT/hf.err >> $OUT/hf.jsonl
