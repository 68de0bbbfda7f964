#!/usr/bin/env bash
# World-cache update rounds in a cold cache's first frames (forty-first session; the kept
# form of cache_rounds.sh's experiment), on the device (H200), one warm machine. Carry .gl,
# .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari_base` (28cf034) and
# `solari` (the change: 4 rounds in the first 8 frames by default).
#   1. error: atrous_plane_2026-11-26/kernel_error.sh over "solari_base solari" (960x540,
#      defaults with the fallback denoiser, against a 1024-spp full-bounce reference),
#      frames 4, 8, 16, 32 and the mean of frames 121-136.
#   2. first frames: `solari render interior --frames 16 --time-every 1 --report` at
#      1920x1080 with each binary (per-frame pass times: $OUT/first_frames.txt).
#   3. time: ab_passes_h200.sh, defaults with the fallback denoiser, cornell_box and
#      interior, 300 frames, two interleaved reps.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT" /root/first
ERROR_BINS="solari_base solari" RUNS="4:1 8:1 16:1 32:1 136:16" \
  bash benches/results/restir_half_2026-11-27/run.sh error
f=$(scene_file interior)
for b in solari_base solari; do
  /root/bins/$b render "$f" --mode realtime --denoiser fallback --frames 16 --time-every 1 \
    --size 1920x1080 --out /root/first/x.png --report /root/first/$b.jsonl > /dev/null 2>&1
  python3 - /root/first/$b.jsonl "$b" >> "$OUT/first_frames.txt" <<'PY'
import json, sys
print("##", sys.argv[2], "interior 1920x1080: frame, world_cache_update ms, world_cache_blend ms, GPU span ms")
for line in open(sys.argv[1]):
    d = json.loads(line)
    t = {p["pass"]: p["gpu_ms"] for p in d["passes"]}
    print(d["frame"], t.get("world_cache_update"), t.get("world_cache_blend"), d.get("gpu_span_ms"))
PY
done
BINS="solari_base solari" TAG=time FLAGS="--denoiser fallback" SCENES="cornell_box interior" \
  bash benches/results/restir_half_2026-11-27/run.sh time
