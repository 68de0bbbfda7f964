#!/usr/bin/env bash
# Thirty-ninth session: the frame loop timing one frame in N (`--time-every`, default 8)
# against every frame (`--time-every 1`, the old behaviour): GPU frame time (passes' means),
# span and wall per frame. 1920x1080, 300 frames, fallback denoiser, two interleaved reps.
# Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT/every"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
S=/root/bins/solari
UP="--gi path --specular-gi on --di-reuse none"
CONFIGS=(
  "50-path-nodi|cornell_box|--internal-scale 0.5 $UP"
  "50-path-nodi|sun_boxes|--internal-scale 0.5 $UP"
  "67-path-nodi|cornell_box|--internal-scale 0.67 $UP"
  "67-path-nodi|interior|--internal-scale 0.67 $UP"
  "default|cornell_box|"
  "default|sun_boxes|"
  "default|many_lights|"
  "default|interior|"
  "default|metal_rough_spheres|"
  "default|emissive_strength_test|"
  "default|furnace_sphere|"
  "default|furnace_uniform|"
)
for rep in 1 2; do
  for c in "${CONFIGS[@]}"; do
    IFS='|' read -r name scene flags <<< "$c"
    for every in 1 8; do
      $S render "$(scene_file "$scene")" --mode realtime --size 1920x1080 --frames 300 \
        --denoiser fallback $flags --time-every $every --out /tmp/x.png --json \
        > "$OUT/every/${scene}_${name}_every${every}_$rep.json" 2>/dev/null
    done
  done
done
cd "$OUT" && tar czf every.tar.gz every
python3 - <<'PY' > "$OUT/every_table.txt"
import json, glob, statistics as st, collections, os
runs = collections.defaultdict(list)
for f in glob.glob("every/*.json"):
    raw = open(f).read().strip().splitlines()
    if raw:
        runs[os.path.basename(f).rsplit("_", 1)[0]].append(json.loads(raw[-1]))
print("| run | passes' sum ms | span ms | wall ms | wall / sum |")
print("|---|---|---|---|---|")
for k in sorted(runs):
    ds = runs[k]
    med = lambda key: st.median(d[key] for d in ds) if all(d.get(key) is not None for d in ds) else float("nan")
    g, s, w = med("gpu_frame_ms"), med("gpu_span_ms"), med("wall_frame_ms")
    print(f"| {k} | {g:.3f} | {s:.3f} | {w:.3f} | {w/g:.3f} |")
PY
rm -rf every
cat "$OUT/every_table.txt"
