#!/usr/bin/env bash
# Thirty-seventh session, fourth and fifth H200 calls: the shipped upscale guide (`--upscale-guide`,
# default on) against it off. Wrappers in .dev/bins.tar.xz: o67/o50 (`--internal-scale 0.67 /
# 0.50 --upscale-guide off`), g67/g50 (the default, guided), t67off/t67on (0.67 with path GI
# and no DI reuse, guide off/on), t100cn (native cache GI, no DI reuse, no antialiasing).
#   error: orbit_error.sh over o67 g67 o50 g50, four main scenes, frames 32 and 96;
#   time:  the four main scenes along the orbit, t67off t67on t100cn, 1920x1080, 300 frames.
set -u
mkdir -p "$OUT"
SCENES="interior many_lights sun_boxes cornell_box" FRAMES="32 96" BINS="o67 g67 o50 g50" \
  bash benches/results/apart_2026-11-27/orbit_error.sh > "$OUT/orbit_error.log" 2>&1
TAG=guide FLAGS="--denoiser fallback --camera-path orbit" BINS="t67off t67on t100cn" REPS=2 \
  bash benches/results/gi_cold_2026-11-27/run.sh time > "$OUT/time.log" 2>&1
cat "$OUT/orbit_error.csv"; grep -E "##|GPU frame|wall|gbuffer |upscale" "$OUT/guide_table.txt"
cd "$OUT" && tar czf all.tar.gz * && ls | grep -v '^all.tar.gz$' | xargs rm -f
