#!/usr/bin/env bash
# The raster and traced G-buffers side by side on every shared scene, with frames in flight,
# on the H200 (device tool), one command. Issue 17: "G-buffer <= 0.5 ms on every shared scene",
# "wall frame time within 10% of GPU frame time", and the light-tiles check of the
# criterion-vs-CLI table (benches/RESULTS.md): after a compute G-buffer the light tiles should
# cost what the bench measures alone.
#
# Needs, carried in the working tree: .gl/ (Vulkan loader packages, see the device README),
# .dev/solari (a stripped release build of the commit under test) and .dev/scenes (a copy of
# ../shared/scenes). Usage (device command):
#   bash benches/results/gbuffer_h200.sh
# Per scene and producer: `solari render --mode realtime --gi cache --denoiser fallback
# --frames 400 --frames-in-flight 2 --size 1920x1080 --json --report ...` (per-pass GPU times
# per frame, wall and GPU frame time in the summary), raster, traced, then auto (the choice it
# makes, in its log). Locally: SOLARI_BIN=target/release/solari RESULTS=/tmp/g OUT=/tmp/o
# SIZE=160x90 FRAMES=8 bash benches/results/gbuffer_h200.sh (SCENES and MODES narrow the run) Everything lands in $OUT/gbuffer_h200.tar.gz (the device
# tool returns at most 8 files).
set -u
source benches/results/device_env.sh
BIN=${SOLARI_BIN:-.dev/solari}
R=${RESULTS:-/root/gbuffer}
mkdir -p "$R"
SIZE=${SIZE:-1920x1080}
FRAMES=${FRAMES:-400}
SCENES=${SCENES:-$(ls .dev/scenes)}
MODES=${MODES:-raster traced auto}
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
for s in $SCENES; do
  f=$(ls .dev/scenes/"$s"/*.gltf 2>/dev/null | head -n 1)
  [ -n "$f" ] || continue
  for g in $MODES; do
    echo "== $s $g $(date -u +%T)" >&2
    RUST_LOG=info "$BIN" render "$f" --mode realtime --gi cache --denoiser fallback \
      --gbuffer "$g" --frames "$FRAMES" --frames-in-flight 2 --size "$SIZE" --json \
      --report "$R/${s}_$g.jsonl" --out "$R/${s}_$g.png" > "$R/${s}_$g.json" \
      2> "$R/${s}_$g.log"
    grep -h "G-buffer auto" "$R/${s}_$g.log" >&2
  done
  rm -f "$R/${s}"_*.png
done
mkdir -p "$OUT"
tar czf "$OUT/gbuffer_h200.tar.gz" -C "$R" .
python3 - "$R" <<'PY' || true
import json, os, sys, glob
r = sys.argv[1]
print(f"{'scene':24} {'asked':7} {'used':7} {'gbuffer ms':>10} {'tiles ms':>9} {'GPU ms':>8} {'wall ms':>8}")
for path in sorted(glob.glob(os.path.join(r, "*.json"))):
    try:
        d = json.load(open(path))
    except Exception:
        continue
    p = d.get("passes", {})
    ms = lambda n: (p.get(n) or {}).get("mean_ms") or float("nan")
    scene, asked = os.path.basename(path)[:-5].rsplit("_", 1)
    print(f"{scene:24} {asked:7} {d.get('gbuffer', '?'):7} {ms('gbuffer'):10.3f} "
          f"{ms('light_tiles'):9.4f} {d.get('gpu_frame_ms') or float('nan'):8.3f} "
          f"{d.get('wall_frame_ms') or float('nan'):8.3f}")
PY
