#!/usr/bin/env bash
# One device command (nvidia-h200) that runs this session's short measurements and then
# starts the remaining soak chain, so the machine is held once:
#   1. issue 16's light-tiles check: the light_tiles bench (alone and after the traced
#      G-buffer) against the CLI on four scenes (bench_vs_cli_h200.sh, BENCHES=light_tiles);
#   2. issue 17: raster, traced and auto G-buffers on every shared scene (gbuffer_h200.sh);
#   3. issue 17: internal scale and the temporal upscaler (upscale_h200.sh);
#   4. issue 15: the soak chain (soak_parallel_h200.sh start, SEQUENTIAL=1), which later
#      `soak_parallel_h200.sh poll` commands follow.
# Needs .gl, .dev/solari, .dev/bench.tar.xz (solari + light_tiles + testdata) and .dev/scenes
# carried, all built from the commit under test (.dev/SOLARI_COMMIT). Results of 1-3 come
# back as three archives in $OUT.
set -u
cat .dev/SOLARI_COMMIT
BENCHES=light_tiles RAYS=0 RESULTS=/root/tiles timeout 200 bash benches/results/bench_vs_cli_h200.sh
python3 benches/results/bench_vs_cli.py /root/tiles || true
timeout 220 bash benches/results/gbuffer_h200.sh
timeout 150 bash benches/results/upscale_h200.sh
SEQUENTIAL=1 RUNS=${RUNS:-"furnace_uniform: furnace_uniform:1000 furnace_sphere: furnace_sphere:1000 emissive_strength_test:1000 many_lights: many_lights:1000 metal_rough_spheres: metal_rough_spheres:1000"} \
  bash benches/results/soak_parallel_h200.sh start
