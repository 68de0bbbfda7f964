#!/usr/bin/env bash
# Thirty-ninth session: the upscaler's own-surface choice moved into a function of its own
# (`own_surface`, for its CPU twin): its pass time along the orbit before (solari_before) and
# after (solari), 1920x1080 output at 0.67 internal scale, path GI, no DI reuse, guide on,
# 300 frames, fallback denoiser, three interleaved reps. Carry .gl, .dev/bins.tar.xz and
# .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT/own"
UP="--internal-scale 0.67 --gi path --specular-gi on --di-reuse none --camera-path orbit"
for rep in 1 2 3; do
  for scene in interior many_lights cornell_box; do
    for b in solari_before solari; do
      /root/bins/$b render "$(scene_file "$scene")" --mode realtime --size 1920x1080 --frames 300 \
        --denoiser fallback $UP --out /tmp/x.png --json > "$OUT/own/${scene}_${b}_$rep.json" 2>/dev/null
    done
  done
done
cd "$OUT" && tar czf own.tar.gz own && python3 - <<'PY' | tee own_table.txt
import json, glob, os, statistics as st, collections
r = collections.defaultdict(list)
for f in glob.glob("own/*.json"):
    d = json.loads(open(f).read().strip().splitlines()[-1])
    r[os.path.basename(f).rsplit("_", 1)[0]].append(d)
print("| run | temporal_upscale ms | upscale_guide ms | frame ms |")
print("|---|---|---|---|")
for k in sorted(r):
    ds = r[k]
    m = lambda p: st.median(d["passes"][p]["mean_ms"] for d in ds)
    print(f"| {k} | {m('temporal_upscale'):.4f} | {m('upscale_guide'):.4f} | {st.median(d['gpu_frame_ms'] for d in ds):.3f} |")
PY
rm -rf own
