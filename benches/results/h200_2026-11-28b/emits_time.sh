#!/usr/bin/env bash
# Thirty-eighth session: the emission-aware guide's cost along the orbit. Wrappers in
# .dev/bins.tar.xz (.dev/SOLARI_COMMIT): t67head / t50head (e9cd14d, the depth-only guide) and
# t67on / t50on (the working tree: an emitter and what lies around it are two surfaces) at
# internal scale 0.67 / 0.5, path GI, specular on, no DI reuse; t100cn native cache GI.
# Four main scenes, 1920x1080, 300 frames, two interleaved reps.
set -u
mkdir -p "$OUT"
TAG=emits FLAGS="--denoiser fallback --camera-path orbit" BINS="t67head t67on t50head t50on t100cn" REPS=2 \
  bash benches/results/gi_cold_2026-11-27/run.sh time > "$OUT/time.log" 2>&1
grep -E "##|GPU frame|wall|upscale" "$OUT/emits_table.txt"
cd "$OUT" && tar czf all.tar.gz * && ls | grep -v '^all.tar.gz$' | xargs rm -f
