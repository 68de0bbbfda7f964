#!/usr/bin/env bash
# Follow-up to start2.sh (H200): per-pass GPU times of the frames `--time-every 8` times
# (0, 8, 16, ...) in `solari render interior --frames 200 --size 1920x1080 --report`, the
# defaults and `--gi-shade-apart off` (EXTRAS: other flag sets, separated by ';').
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
f=$(scene_file interior)
IFS=";" read -ra LIST <<< "${EXTRAS:-;--gi-shade-apart off}"
for extra in "${LIST[@]}"; do
  tag=render$(echo "$extra" | tr -c "a-z0-9\n" "_")
  /root/bins/solari render "$f" --mode realtime --size 1920x1080 --frames 200 --time-every 8 \
    --report "$OUT/start3_$tag.jsonl" $extra --out /tmp/x.exr > "$OUT/start3_$tag.txt" 2>&1
  python3 - "$OUT/start3_$tag.jsonl" "$tag" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print(sys.argv[2])
for r in rows:
    if r["frame"] in (0, 8, 16, 24):
        print(" frame", r["frame"], "span", round(r["gpu_span_ms"], 2),
              [(p["pass"], round(p["gpu_ms"], 3)) for p in r["passes"] if p["gpu_ms"]])
PY
  grep -i "wall" "$OUT/start3_$tag.txt" | head -3
done
