#!/usr/bin/env bash
# Thirty-ninth session: where a frame's wall time beyond its GPU span goes. Wall ms per frame
# with the per-pass timestamps on (shipped) and off (SOLARI_EXP_NO_TIMESTAMPS, a temporary
# hook), with 2 and 3 frames in flight, on the cheapest upscaled frames and two defaults.
# 1920x1080, 300 frames, fallback denoiser, three interleaved reps.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT/wall"
S=/root/bins/solari
UP="--gi path --specular-gi on --di-reuse none"
CONFIGS=(
  "50|cornell_box|--internal-scale 0.5 $UP"
  "50|sun_boxes|--internal-scale 0.5 $UP"
  "default|cornell_box|"
  "default|interior|"
)
for rep in 1 2 3; do
  for c in "${CONFIGS[@]}"; do
    IFS='|' read -r name scene flags <<< "$c"
    for fif in 2 3; do
      for ts in on off; do
        if [ $ts = off ]; then export SOLARI_EXP_NO_TIMESTAMPS=1; else unset SOLARI_EXP_NO_TIMESTAMPS; fi
        $S render "$(scene_file "$scene")" --mode realtime --size 1920x1080 --frames 300 \
          --denoiser fallback $flags --frames-in-flight $fif --out /tmp/x.png --json \
          > "$OUT/wall/${scene}_${name}_fif${fif}_ts${ts}_$rep.json" 2>/dev/null
      done
    done
  done
done
cd "$OUT" && tar czf wall.tar.gz wall
python3 - <<'PY' > "$OUT/wall_table.txt"
import json, glob, statistics as st, collections, os
runs = collections.defaultdict(list)
for f in glob.glob("wall/*.json"):
    raw = open(f).read().strip().splitlines()
    if raw:
        runs[os.path.basename(f).rsplit("_", 1)[0]].append(json.loads(raw[-1]))
print("| run | passes' sum ms | span ms | wall ms |")
print("|---|---|---|---|")
for k in sorted(runs):
    ds = runs[k]
    med = lambda key: st.median(d[key] for d in ds) if all(d.get(key) is not None for d in ds) else float("nan")
    print(f"| {k} | {med('gpu_frame_ms'):.3f} | {med('gpu_span_ms'):.3f} | {med('wall_frame_ms'):.3f} |")
PY
rm -rf wall
cat "$OUT/wall_table.txt"
