#!/usr/bin/env bash
# Spelled-out taps and children instead of constant-trip loops, on the device (H100/H200), one
# warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; the binaries under
# /root/bins are named in BINS (default: solari_base, before; solari_dn, the denoiser's taps;
# solari, also the traversal's node test).
#   time:  ab_passes_h200.sh over BINS, 1920x1080, defaults with --denoiser fallback, 300
#          frames, two interleaved reps; table by memory_scratch_2026-11-26/ab_variants.py
#   rays:  `bench-rays SCENE --tracer software --frames 200 --presets medium --json` of each
#          binary in RAY_BINS, interleaved, REPS reps, on RAY_SCENES (rays.jsonl)
#   exact: the same frames from each binary of BINS and the first, compared (`--gi off
#          --specular-gi off`, where the renderer is deterministic; 1920x1080, 16 frames)
# Usage: bash benches/results/unrolled_2026-11-26/run.sh time|rays|exact
set -u
source benches/results/device_env.sh
unpack_bins
BINS=${BINS:-solari_base solari_dn solari}
mkdir -p "$OUT"
case "${1:-}" in
  time)
    # The emitter BVH study's `time`, which is exactly this (ab_passes_h200.sh, then the table).
    BINS="$BINS" bash benches/results/emitter_bvh_2026-11-26/run.sh time
    ;;
  rays)
    for rep in $(seq 1 "${REPS:-2}"); do
      for s in ${RAY_SCENES:-interior many_lights furnace_sphere metal_rough_spheres}; do
        for b in ${RAY_BINS:-solari_base solari}; do
          echo "== rays $s $b rep $rep $(date -u +%T)" >&2
          /root/bins/$b bench-rays "$(scene_file "$s")" --tracer software --frames 200 \
            --presets medium --json 2>> "$OUT/rays.log" \
            | sed "s/^{/{\"binary\":\"$b\",\"rep\":$rep,/" >> "$OUT/rays.jsonl"
        done
      done
    done
    python3 - "$OUT/rays.jsonl" <<'PY' | tee "$OUT/rays_table.txt"
import json, sys, statistics
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
key = lambda r: (r["scene"].split("/")[-1], r["binary"])
groups = {}
for r in rows:
    groups.setdefault(key(r), []).append(r)
print("scene binary primary_ms ao_ms (medians over reps)")
for k in sorted(groups):
    g = groups[k]
    print(k[0], k[1], round(statistics.median(r["primary_ms"] for r in g), 4),
          round(statistics.median(r["ao_ms"] for r in g), 4))
PY
    ;;
  exact)
    set -- $BINS
    first=$1
    for s in ${SCENES:-cornell_box sun_boxes many_lights interior}; do
      for b in $BINS; do
        /root/bins/$b render "$(scene_file "$s")" --mode realtime --gi off --specular-gi off \
          --denoiser fallback --frames 16 --size 1920x1080 --out "/root/${s}_$b.exr" > /dev/null 2>&1
      done
      for b in $BINS; do
        echo "$s $b $(/root/bins/solari compare "/root/${s}_$b.exr" "/root/${s}_$first.exr" --json)"
      done
    done | tee "$OUT/exact.txt"
    ;;
  *) echo "usage: $0 time|rays|exact" >&2; exit 2 ;;
esac
