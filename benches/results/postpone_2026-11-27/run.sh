#!/usr/bin/env bash
# The twenty-sixth session's traversal and denoiser experiments (README.md), on the device
# (H100/H200), one warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; the
# binaries under /root/bins are the builds under test and wrappers (README.md lists them).
#   rays: `solari bench-rays` (1920x1080, primary + one cosine hemisphere ray per pixel, 200
#         frames, medians) per binary, interleaved, $REPS reps: interior and many_lights
#         (merged, medium and very-slow), interior two-level (--merge-instances off, medium),
#         the 2048² heightfield (very-slow). JSON lines tagged with the binary in rays.jsonl.
#   time: the emitter BVH study's `run.sh time` over $BINS (defaults with --denoiser fallback,
#         300 frames, two interleaved reps), SCENES as there.
# Usage: BINS="..." bash benches/results/postpone_2026-11-27/run.sh rays|time
set -u
source benches/results/device_env.sh
unpack_bins
BINS=${BINS:-solari}
mkdir -p "$OUT"
case "${1:-}" in
  rays)
    : > "$OUT/rays.jsonl"
    for rep in $(seq 1 "${REPS:-2}"); do
      for b in $BINS; do
        tag() { python3 -c 'import json,sys
for l in sys.stdin:
    l=l.strip()
    if l.startswith("{"):
        d=json.loads(l); d["bin"]=sys.argv[1]; d["rep"]=int(sys.argv[2]); d["case"]=sys.argv[3]; print(json.dumps(d))' "$b" "$rep" "$1" >> "$OUT/rays.jsonl"; }
        for s in ${SCENES:-interior many_lights}; do
          /root/bins/$b bench-rays "$(scene_file "$s")" --tracer software --frames 200 \
            --presets medium,very-slow --json 2>> "$OUT/rays_log.txt" | tag "$s"
        done
        /root/bins/$b bench-rays "$(scene_file interior)" --tracer software --frames 200 \
          --presets medium --merge-instances off --json 2>> "$OUT/rays_log.txt" | tag interior_two_level
        if [ -z "${NO_HEIGHTFIELD:-}" ]; then
          /root/bins/$b bench-rays --heightfield 2048 --tracer software --frames 200 \
            --presets very-slow --json 2>> "$OUT/rays_log.txt" | tag heightfield
        fi
      done
    done
    python3 benches/results/postpone_2026-11-27/rays_table.py "$OUT/rays.jsonl" | tee "$OUT/rays_table.txt"
    ;;
  time) BINS="$BINS" bash benches/results/emitter_bvh_2026-11-26/run.sh time ;;
  *) echo "usage: $0 rays|time" >&2; exit 2 ;;
esac
