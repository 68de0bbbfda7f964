#!/usr/bin/env bash
# The criterion benches per component against the CLI's figures for the same scenes and
# settings, on the H200 (device tool), one command. Issue 16: "cargo bench per component on
# the H200 gives figures within 5% of the CLI's".
#
# Built here (the device machine has no toolchain), from one commit:
#   cargo build --release -p solari-app --bin solari
#   cargo bench --no-run --workspace --message-format=json   # the bench binaries' paths
# then the six bench binaries (traversal, light_tiles, restir_di, world_cache, fallback,
# frame) and `solari`, stripped, with a copy of crates/solari-testdata as testdata/, packed
# into .dev/bench.tar.xz (carry limit). Carry .gl and .dev. Usage (device command):
#   bash benches/results/bench_vs_cli_h200.sh
# Each bench binary is run as `cargo bench` runs it (`--bench`), with criterion's estimates
# written under criterion/. Everything lands in one archive, $OUT/bench_vs_cli.tar.gz (the
# device tool returns at most 8 files). CLI side, per scene: `solari render --mode realtime --gi cache
# --denoiser fallback` (per-pass GPU times per frame, the same passes the benches time) and
# `solari bench-rays`. benches/results/bench_vs_cli.py turns both into the table.
# BENCHES narrows the benches run (a bench binary missing from the archive is skipped);
# RAYS=0 skips bench-rays (only the traversal rows need it).
set -u
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
B=/root/bench
R=${RESULTS:-/root/results}
mkdir -p "$B" "$R/cli"
tar xJf .dev/bench.tar.xz -C "$B"
export SOLARI_TESTDATA=$B/testdata SOLARI_SHARED_SCENES=$PWD/.dev/scenes
export SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
export SOLARI_BENCH_SCENES=${SCENES// /,}
export CRITERION_HOME=$R/criterion
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > "$R/gpu.csv"
for s in $SCENES; do
  f=$(ls "$B/testdata/scenes/$s"/*.gltf | head -n 1)
  echo "== $s realtime $(date -u +%T)" >&2
  "$B/solari" render "$f" --mode realtime --gi cache --denoiser fallback --frames 400 \
    --size 1920x1080 --report "$R/cli/realtime_$s.jsonl" --out "$R/cli/realtime_$s.png" \
    2> "$R/cli/realtime_$s.log"
  [ "${RAYS:-1}" = 1 ] || continue
  echo "== $s bench-rays $(date -u +%T)" >&2
  "$B/solari" bench-rays "$f" --frames 200 --json > "$R/cli/rays_$s.jsonl" \
    2> "$R/cli/rays_$s.log"
done
for b in ${BENCHES:-traversal light_tiles restir_di world_cache fallback frame}; do
  [ -x "$B/$b" ] || { echo "== bench $b: not in the archive, skipped" >&2; continue; }
  echo "== bench $b $(date -u +%T)" >&2
  "$B/$b" --bench --warm-up-time 2 --measurement-time 4 > "$R/bench_$b.log" 2>&1
  echo "exit $?" >> "$R/bench_$b.log"
done
echo "== done $(date -u +%T)" >&2
mkdir -p "$OUT"
tar czf "$OUT/bench_vs_cli.tar.gz" -C "$R" .
