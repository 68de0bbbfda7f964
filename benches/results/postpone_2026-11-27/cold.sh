#!/usr/bin/env bash
# A binary's first runs on a fresh machine (no cached shaders for it): the default frame three
# times in a row, then --quality auto twice, with the SM clock and P-state sampled every 100
# ms meanwhile (nvidia-smi). Usage: BIN=solari_cold1 bash benches/results/postpone_2026-11-27/cold.sh
set -u
source benches/results/device_env.sh
unpack_bins
B=/root/bins/${BIN:-solari_cold1}
f=$(scene_file cornell_box)
mkdir -p "$OUT"
nvidia-smi --query-gpu=timestamp,pstate,clocks.sm,clocks.mem,power.draw,utilization.gpu --format=csv -lms 100 > "$OUT/smi.csv" 2>&1 &
SMI=$!
for run in 1 2 3; do
  s=$(date +%s.%N)
  $B render "$f" --mode realtime --denoiser fallback --size 1920x1080 --frames 300 --json --out /tmp/x.exr > "$OUT/default$run.json" 2> /dev/null
  e=$(date +%s.%N)
  python3 -c "import json,sys; d=json.load(open('$OUT/default$run.json')); print('default run $run: gpu', round(d['gpu_frame_ms'],4), 'wall', round(d['wall_frame_ms'],4), 'process s', round($e-$s,2))"
done
for run in 1 2; do
  $B render "$f" --mode realtime --quality auto --denoiser fallback --size 1920x1080 --frames 3 --json --out /tmp/x.exr > "$OUT/auto$run.json" 2> /dev/null
  python3 -c "import json; q=json.load(open('$OUT/auto$run.json'))['quality']; print('auto run $run: 100-path predicted', round(q['predicted_ms_per_setting']['100-path'],4), 'probe s', round(q['probe_s'],2))"
done
kill $SMI
python3 - "$OUT/smi.csv" <<'PY'
import sys, collections
rows = [l.strip() for l in open(sys.argv[1]) if l.strip() and not l.startswith("timestamp")]
print(len(rows), "samples; pstate/clock changes:")
last = None
for r in rows:
    f = [x.strip() for x in r.split(",")]
    key = (f[1], f[2])
    if key != last:
        print("  ", f[0], f[1], f[2], f[3], f[4], f[5])
        last = key
PY
