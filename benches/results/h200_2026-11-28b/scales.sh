#!/usr/bin/env bash
# Thirty-eighth session, first H200 call: does an internal scale between 0.67 and native, with
# the upscaler's guide, beat native cache GI on interior along the orbit at equal GPU time?
# Wrappers in .dev/bins.tar.xz: t67on / t72 / t75 / t80 (internal scale 0.67 / 0.72 / 0.75 /
# 0.8, path GI, specular GI on, no DI reuse, guide on by default), t100cn (native cache GI,
# specular off, no DI reuse, no antialiasing).
#   error: quality_h200.sh's orbit phase on interior (960x540, frames 32 and 96, 1024-spp
#          references) for 72-, 75- and 80-path-nodi;
#   time:  interior along the orbit, 1920x1080, 300 frames, two interleaved reps.
set -u
mkdir -p "$OUT"
SCENES=interior SETTINGS="72-path-nodi 75-path-nodi 80-path-nodi" PHASES=orbit \
  bash benches/results/quality_h200.sh > "$OUT/orbit.log" 2>&1
TAG=scales FLAGS="--denoiser fallback --camera-path orbit" BINS="t67on t72 t75 t80 t100cn" REPS=2 \
  SCENES=interior bash benches/results/gi_cold_2026-11-27/run.sh time > "$OUT/time.log" 2>&1
cat "$OUT/quality_table.csv"; grep -E "##|GPU frame|wall|upscale" "$OUT/scales_table.txt"
cd "$OUT" && tar czf all.tar.gz * && ls | grep -v '^all.tar.gz$' | xargs rm -f
