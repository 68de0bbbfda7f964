#!/usr/bin/env bash
# Soaks on the device (H200), forty-second session. Carry .gl, .dev/bins.tar.xz and
# .dev/SOLARI_COMMIT (`solari`: the commit named there). Every pass's non-finite detector on,
# every frame; summaries (with the eight slowest frames by wall time) in $OUT/soak_*.json.
#   toggles: `solari soak interior --frames 4000 --toggle-lights 50 --size 1920x1080`, the
#            defaults and `--gi restir --gi-quarter-rate`.
#   long:    `solari soak interior --frames 100000 --toggle-lights 1000 --camera-path orbit
#            --size 1920x1080 --gi restir --gi-quarter-rate` (issue 18's stability run).
# Usage: bash benches/results/h200_2026-11-29/soak.sh toggles|long
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
run() {
  local tag=$1 scene=$2; shift 2
  /root/bins/solari soak "$(scene_file "$scene")" --size 1920x1080 "$@" \
    > "$OUT/soak_$tag.json" 2> "$OUT/soak_$tag.log"
  echo "$tag rc=$?"
  python3 - "$OUT/soak_$tag.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(" clean", d["clean"], "overflows", d["cache_overflows"], "gpu", d["gpu_frame_ms"], "wall", d["wall_frame_ms"])
print(" slowest", [(f["frame"], round(f["wall_ms"], 1), f["frames_since_toggle"]) for f in d["slowest_wall_frames"]])
PY
}
case "${1:-}" in
  toggles)
    run interior interior --frames 4000 --toggle-lights 50
    run interior_restir_quarter interior --frames 4000 --toggle-lights 50 --gi restir --gi-quarter-rate ;;
  long)
    run interior_restir_quarter_100k interior --frames 100000 --toggle-lights 1000 --camera-path orbit \
      --gi restir --gi-quarter-rate --progress-every 10000 ;;
  *) echo "usage: $0 toggles|long" >&2; exit 2 ;;
esac
