#!/usr/bin/env bash
# Thirty-ninth session: the frame's GPU span (first pass's start to last pass's end, new in
# the report as `gpu_span_ms`) beside the passes' sum and the wall time, for the default
# frame, the cheap upscaled frames and the furnaces; and what `--quality auto --budget-ms 4`
# picks and costs on the furnaces and interior. 1920x1080, 300 frames, fallback denoiser,
# two interleaved reps; one JSON per run under $OUT/span/. Carry .gl, .dev/bins.tar.xz and
# .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT/span"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
S=/root/bins/solari
UP="--gi path --specular-gi on --di-reuse none"
CONFIGS=(
  "default|cornell_box|"
  "default|sun_boxes|"
  "default|many_lights|"
  "default|interior|"
  "default|furnace_sphere|"
  "default|furnace_uniform|"
  "nodi|furnace_sphere|--di-reuse none"
  "nodi|furnace_uniform|--di-reuse none"
  "auto4|furnace_sphere|--quality auto --budget-ms 4"
  "auto4|furnace_uniform|--quality auto --budget-ms 4"
  "auto4|interior|--quality auto --budget-ms 4"
  "50-path-nodi|cornell_box|--internal-scale 0.5 $UP"
  "50-path-nodi|sun_boxes|--internal-scale 0.5 $UP"
  "67-path-nodi|cornell_box|--internal-scale 0.67 $UP"
  "67-path-nodi|interior|--internal-scale 0.67 $UP"
)
for rep in 1 2; do
  for c in "${CONFIGS[@]}"; do
    IFS='|' read -r name scene flags <<< "$c"
    $S render "$(scene_file "$scene")" --mode realtime --size 1920x1080 --frames 300 \
      --denoiser fallback $flags --out /tmp/x.png --json \
      > "$OUT/span/${scene}_${name}_$rep.json" 2> "$OUT/span/${scene}_${name}_$rep.log"
  done
done
cd "$OUT" && tar czf span.tar.gz span && rm -rf span
python3 - <<'PY' > "$OUT/span_table.txt"
import json, tarfile, statistics as st, collections
t = tarfile.open("span.tar.gz")
runs = collections.defaultdict(list)
for m in t.getmembers():
    if m.name.endswith(".json"):
        raw = t.extractfile(m).read().decode().strip().splitlines()
        if not raw:
            continue
        d = json.loads(raw[-1])
        key = m.name.split("/")[-1].rsplit("_", 1)[0]
        runs[key].append(d)
print("| run | passes' sum ms | span ms | wall ms | wall/span | wall/sum | quality |")
print("|---|---|---|---|---|---|---|")
for k in sorted(runs):
    ds = runs[k]
    g = st.median(d["gpu_frame_ms"] for d in ds)
    s = st.median(d["gpu_span_ms"] for d in ds)
    w = st.median(d["wall_frame_ms"] for d in ds)
    q = ds[0].get("quality")
    q = f"{q.get('chosen')} (pred {q.get('predicted_ms'):.2f})" if isinstance(q, dict) else ""
    print(f"| {k} | {g:.3f} | {s:.3f} | {w:.3f} | {w/s:.3f} | {w/g:.3f} | {q} |")
PY
cat "$OUT/span_table.txt"
