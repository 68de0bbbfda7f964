#!/usr/bin/env bash
# The first frames' wall time on the device (H200), forty-second session: which frames of a
# soak are slow and why. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT. interior at
# 1920x1080, 100 frames of `solari soak` (detector on every pass) with the defaults, with
# `--cache-warm-up-rounds 1`, with `--check-finite` off in `render` instead (`render
# --frames 16 --time-every 1 --report`: GPU span and wall per frame), and with `--gi restir
# --gi-quarter-rate`. Output: $OUT/start_*.json|jsonl and the table it prints.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
f=$(scene_file interior)
soak() {
  local tag=$1; shift
  /root/bins/solari soak "$f" --size 1920x1080 --frames 100 --progress-every 0 "$@" \
    > "$OUT/start_$tag.json" 2> "$OUT/start_$tag.log"
  python3 - "$OUT/start_$tag.json" "$tag" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(sys.argv[2], "wall p50", round(d["wall_frame_ms"]["p50"], 2), "slowest",
      [(f["frame"], round(f["wall_ms"], 1)) for f in d["slowest_wall_frames"]])
PY
}
soak defaults
soak rounds1 --cache-warm-up-rounds 1
soak restir_quarter --gi restir --gi-quarter-rate
for extra in "" "--check-finite"; do
  tag=render${extra:+_checked}
  /root/bins/solari render "$f" --mode realtime --size 1920x1080 --frames 16 --time-every 1 \
    --report "$OUT/start_$tag.jsonl" $extra --out /tmp/x.exr > "$OUT/start_$tag.txt" 2>&1
  python3 - "$OUT/start_$tag.jsonl" "$tag" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print(sys.argv[2], "keys", sorted(rows[0].keys()))
for r in rows[:12]:
    print(" ", r.get("frame"), {k: r[k] for k in r if k in ("gpu_ms", "wall_ms", "gpu_span_ms")})
PY
done
