#!/usr/bin/env bash
# Issue 16's last gap: the light-tiles bench against the CLI frame, with the bench's new
# frames-in-flight case (`.../in_flight`: G-buffer then tiles, frames submitted back to back)
# beside the pass alone and after the G-buffer with a wait per frame, and the SM clock
# sampled every 50 ms during each run (nvidia-smi, read only: nothing is set). Carry .gl and
# .dev (bench.tar.xz with light_tiles, solari and testdata; scenes). Usage (device command):
#   bash benches/results/tiles_clocks_h200.sh
# Results in $OUT/tiles_clocks.tar.gz; the table by
#   python3 benches/results/bench_vs_cli.py <unpacked folder>
set -u
source benches/results/device_env.sh
B=/root/bench
R=${RESULTS:-/root/results}
mkdir -p "$B" "$R/cli" "$R/clocks" "$OUT"
tar xJf .dev/bench.tar.xz -C "$B"
export SOLARI_TESTDATA=$B/testdata SOLARI_SHARED_SCENES=$PWD/.dev/scenes
export SCENES=${SCENES:-interior many_lights cornell_box sun_boxes}
export SOLARI_BENCH_SCENES=${SCENES// /,}
export CRITERION_HOME=$R/criterion
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > "$R/gpu.csv"
clocks() { # label: sample the SM clock until killed
  nvidia-smi --query-gpu=timestamp,clocks.sm,power.draw,utilization.gpu --format=csv,noheader \
    -lms 50 > "$R/clocks/$1.csv" 2>/dev/null &
  echo $!
}
for s in $SCENES; do
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  echo "== $s realtime $(date -u +%T)" >&2
  pid=$(clocks "cli_$s")
  "$B/solari" render "$f" --mode realtime --gi cache --denoiser fallback --frames 400 \
    --size 1920x1080 --report "$R/cli/realtime_$s.jsonl" --out "$R/cli/realtime_$s.png" \
    2> "$R/cli/realtime_$s.log"
  kill "$pid"
done
echo "== bench light_tiles $(date -u +%T)" >&2
pid=$(clocks bench_light_tiles)
"$B/light_tiles" --bench --warm-up-time 2 --measurement-time 4 > "$R/bench_light_tiles.log" 2>&1
echo "exit $?" >> "$R/bench_light_tiles.log"
kill "$pid"
echo "== done $(date -u +%T)" >&2
tar czf "$OUT/tiles_clocks.tar.gz" -C "$R" .
