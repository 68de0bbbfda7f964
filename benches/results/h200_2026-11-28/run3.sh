#!/usr/bin/env bash
# Thirty-seventh session, third H200 call: the upscaler guided by an output-resolution depth
# (experiments/upscale_output_depth_guide_env.patch; SOLARI_EXP_GUIDE=1 traces a G-buffer at
# the output size and gives its depth to the upscaler). Wrappers in .dev/bins.tar.xz:
# x67/x50 (the patched build without the variable, internal scale 0.67/0.5), g67/g50 (with
# it), t67/tg67 (0.67 with path GI and no DI reuse, without/with), t100cn (native, cache GI,
# no DI reuse, antialiasing off: the cheapest native grid point).
#   error: orbit_error.sh over x67 g67 x50 g50 on the four main scenes, frames 32 and 96;
#   time:  interior along the orbit, t67 tg67 t100cn, 1920x1080, 300 frames, two reps.
set -u
mkdir -p "$OUT"
SCENES="interior many_lights sun_boxes cornell_box" FRAMES="32 96" BINS="x67 g67 x50 g50" \
  bash benches/results/apart_2026-11-27/orbit_error.sh > "$OUT/orbit_error.log" 2>&1
SCENES=interior TAG=guide FLAGS="--denoiser fallback --camera-path orbit" BINS="t67 tg67 t100cn" REPS=2 \
  bash benches/results/gi_cold_2026-11-27/run.sh time > "$OUT/time.log" 2>&1
cat "$OUT/orbit_error.csv"; grep -E "##|GPU frame|wall|gbuffer |temporal_upscale" "$OUT/guide_table.txt"
cd "$OUT" && tar czf all.tar.gz * && ls | grep -v '^all.tar.gz$' | xargs rm -f
