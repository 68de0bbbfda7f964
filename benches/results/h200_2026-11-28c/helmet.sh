#!/usr/bin/env bash
# Thirty-ninth session: the upscaler's guide on a scene with emissive textures
# (damaged_helmet, carried as .dev/damaged_helmet, a copy of ../shared/scenes/damaged_helmet):
# orbit camera at internal scale 0.67 (path GI, no DI reuse), guide on (the default) against
# off, and the default frame. 1920x1080, 300 frames, fallback denoiser, two interleaved reps.
# Carry .gl, .dev/bins.tar.xz, .dev/SOLARI_COMMIT and .dev/damaged_helmet.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT/helmet"
S=/root/bins/solari
H=.dev/damaged_helmet/DamagedHelmet.gltf
UP="--internal-scale 0.67 --gi path --specular-gi on --di-reuse none --camera-path orbit"
for rep in 1 2; do
  $S render $H --mode realtime --size 1920x1080 --frames 300 --denoiser fallback $UP \
    --out /tmp/x.png --json > "$OUT/helmet/guide_on_$rep.json" 2>/dev/null
  $S render $H --mode realtime --size 1920x1080 --frames 300 --denoiser fallback $UP \
    --upscale-guide off --out /tmp/x.png --json > "$OUT/helmet/guide_off_$rep.json" 2>/dev/null
  $S render $H --mode realtime --size 1920x1080 --frames 300 --denoiser fallback \
    --out /tmp/x.png --json > "$OUT/helmet/default_$rep.json" 2>/dev/null
done
cd "$OUT" && python3 - <<'PY' | tee helmet_table.txt
import json, glob, os
for f in sorted(glob.glob("helmet/*.json")):
    raw = open(f).read().strip().splitlines()
    if not raw:
        print(f, "no output"); continue
    d = json.loads(raw[-1]); p = d["passes"]
    ms = lambda k: p.get(k, {}).get("mean_ms") or 0.0
    print(f"{os.path.basename(f)}: passes {d['gpu_frame_ms']:.3f} span {d['gpu_span_ms']:.3f} wall {d['wall_frame_ms']:.3f} guide {ms('upscale_guide'):.3f} upscaler {ms('temporal_upscale'):.3f}")
PY
