#!/usr/bin/env bash
# The emitter BVH for ReSTIR DI's BRDF-sampled candidates, on the device (H100/H200), one
# warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; the binaries under
# /root/bins are solari_base (the commit before), solari (the change) and solari_nobrdf (a
# wrapper: the base with --brdf-candidates 0, the bar the change can at best reach).
#   time:     ab_passes_h200.sh over the three, 1920x1080, defaults with --denoiser fallback,
#             300 frames, two interleaved reps; table by memory_scratch_2026-11-26/ab_variants.py
#   di-error: direct light alone, 960x540: `--mode reference --max-bounces 1 --pixel-centre
#             --spp $SPP` against `--mode realtime --gi off --specular-gi off --denoiser none`
#             of each binary, for each frames:mean-of pair of $RUNS; `solari compare`.
# Usage: bash benches/results/emitter_bvh_2026-11-26/run.sh time|di-error
set -u
source benches/results/device_env.sh
unpack_bins
BINS=${BINS:-solari_base solari solari_nobrdf}
mkdir -p "$OUT"
case "${1:-}" in
  time)
    RESULTS=/root/ab BINS="$BINS" FLAGS="--denoiser fallback" REPS=${REPS:-2} FRAMES=300 \
      BVH_SCENES=" " SCENES="${SCENES:-cornell_box sun_boxes many_lights interior}" \
      bash benches/results/ab_passes_h200.sh > "$OUT/time_log.txt" 2>&1
    python3 benches/results/memory_scratch_2026-11-26/ab_variants.py /root/ab "$BINS" \
      | tee "$OUT/time_table.txt"
    ;;
  di-error)
    R=/root/dierr
    SPP=${SPP:-1024}
    RUNS=${RUNS:-1:1 8:1 64:16}
    mkdir -p "$R"
    echo "scene,binary,frames,mean_of,rel_mse,rmse,flip,mean_ratio" > "$OUT/di_error.csv"
    for s in ${SCENES:-cornell_box sun_boxes many_lights interior}; do
      f=$(scene_file "$s")
      echo "== $s reference $(date -u +%T)" >&2
      /root/bins/solari render "$f" --mode reference --max-bounces 1 --pixel-centre \
        --spp "$SPP" --size 960x540 --out "$R/${s}_ref.exr" > /dev/null 2>&1
      for b in $BINS; do
        for run in $RUNS; do
          frames=${run%%:*} m=${run#*:}
          n="${s}_${b}_f${frames}_mean$m"
          /root/bins/$b render "$f" --mode realtime --gi off --specular-gi off \
            --denoiser none --frames "$frames" --mean-of "$m" --size 960x540 \
            --out "$R/$n.exr" > "$R/$n.log" 2>&1
          /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref.exr" --json > "$R/$n.compare.json"
          python3 - "$R/$n.compare.json" "$s" "$b" "$frames" "$m" >> "$OUT/di_error.csv" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
a = d.get("all", d)
print(",".join(sys.argv[2:6] + [str(a.get(k)) for k in ("rel_mse", "rmse", "flip", "mean_ratio")]))
PY
          rm -f "$R/$n.exr"
        done
      done
      rm -f "$R/${s}_ref.exr"
    done
    tar czf "$OUT/di_error.tar.gz" -C "$R" .
    cat "$OUT/di_error.csv"
    ;;
  *) echo "usage: $0 time|di-error" >&2; exit 2 ;;
esac
