#!/usr/bin/env bash
# Follow-up to start.sh (H200): the default interior soak's first frames with every frame
# timed (--time-every 1), with path GI shaded in its own dispatch off (--gi-shade-apart off),
# with one frame in flight, and path GI at half rate; 100 frames, 1920x1080.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
f=$(scene_file interior)
soak() {
  local tag=$1; shift
  /root/bins/solari soak "$f" --size 1920x1080 --frames 100 --progress-every 0 "$@" \
    > "$OUT/start2_$tag.json" 2> "$OUT/start2_$tag.log"
  python3 - "$OUT/start2_$tag.json" "$tag" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(sys.argv[2], "wall p50", round(d["wall_frame_ms"]["p50"], 2), "gpu max", d["gpu_frame_ms"]["max"], "slowest",
      [(f["frame"], round(f["wall_ms"], 1)) for f in d["slowest_wall_frames"]])
PY
}
soak defaults
soak time1 --time-every 1
soak apart_off --gi-shade-apart off
soak inflight1 --frames-in-flight 1
soak cache_gi --gi cache
soak denoiser_none --denoiser none
