#!/usr/bin/env bash
# Scale on the H200 (device tool), one command: the whole pipeline on `interior` and on a
# generated field of 1,024 distinct rocks of 10,000 triangles (10.2 M triangles, 1,029
# instances): load, upload with BVH build, renderer set-up, per-pass and wall/GPU frame
# times, memory. Issue 17, "Scale". Needs .gl, .dev/solari (stripped release build of the
# commit under test) and .dev/scenes carried. Usage: bash benches/results/scale_h200.sh
set -u
source benches/results/device_env.sh
BIN=${SOLARI_BIN:-.dev/solari}
R=${RESULTS:-/root/scale}
SIZE=${SIZE:-1920x1080}
FRAMES=${FRAMES:-300}
ROCKS=${ROCKS:-1024x10000}
mkdir -p "$R"
run() {  # name, scene arguments...
  local name=$1; shift
  for g in raster traced; do
    echo "== $name $g $(date -u +%T)" >&2
    RUST_LOG=info "$BIN" render "$@" --mode realtime --gi cache --denoiser fallback \
      --gbuffer "$g" --frames "$FRAMES" --size "$SIZE" --json --out "$R/${name}_$g.png" \
      > "$R/${name}_$g.json" 2> "$R/${name}_$g.log"
    rm -f "$R/${name}_$g.png"
  done
}
run interior .dev/scenes/interior/*.gltf
run rocks --generated "$ROCKS"
mkdir -p "$OUT"
tar czf "$OUT/scale_h200.tar.gz" -C "$R" .
for f in "$R"/*.json; do
  python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(sys.argv[1].split('/')[-1], {k: d.get(k) for k in ['triangles','instances','load_s','upload_s','renderer_build_s','gpu_frame_ms','wall_frame_ms','gbuffer']}, d.get('memory_bytes'))" "$f"
done
