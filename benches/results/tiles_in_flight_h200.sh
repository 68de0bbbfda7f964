#!/usr/bin/env bash
# Does the light-tiles pass's in-frame time depend on frames in flight? The CLI frame with
# one and with two frames in flight, per scene (issue 16's last check; RESULTS "Criterion
# benches against the CLI"). Carry .gl, .dev (solari, scenes). Usage (device command):
#   bash benches/results/tiles_in_flight_h200.sh
set -u
source benches/results/device_env.sh
R=/root/tif; mkdir -p "$R" "$OUT"
for s in ${SCENES:-interior many_lights cornell_box sun_boxes}; do
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  for n in 1 2; do
    .dev/solari render "$f" --mode realtime --gi cache --denoiser fallback --frames 400 \
      --frames-in-flight $n --size 1920x1080 --report "$R/${s}_$n.jsonl" --out "$R/x.png" \
      2> /dev/null
    python3 - "$R/${s}_$n.jsonl" "$s" "$n" <<'PY'
import json, statistics, sys
t = []
for line in open(sys.argv[1]):
    r = json.loads(line)
    if r["frame"] >= 100:
        t += [p["gpu_ms"] for p in r["passes"] if p["pass"] == "light_tiles" and p["gpu_ms"]]
print(f"{sys.argv[2]:14} in flight {sys.argv[3]}: light tiles median {statistics.median(t)*1e3:.2f} us")
PY
  done
done | tee "$OUT/tiles_in_flight.txt"
