#!/usr/bin/env bash
# GI's glossy hits (`--gi-glossy-hits`, fifty-second session) on the device (H100/H200), one
# warm machine (run by the fifty-third session: h100/, README). Carry .gl,
# .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari_base` (the commit before
# the change, a91047a) and `solari` (the change: `--gi-glossy-hits cache`, the default, builds
# GI's initial pass as before, with GI's group 3 now holding the lights), and this script's
# wrappers `solari_lights` and `solari_path` (`--gi-glossy-hits lights` and `path`).
#   time:  ab_passes_h200.sh over the four with the defaults (path GI, fallback denoiser),
#          1920x1080, 300 frames, REPS interleaved reps (default 2), on every shared scene;
#          table by memory_scratch_2026-11-26/ab_variants.py.
#   error: one 1024-path full-bounce reference per scene at 960x540, then `solari`,
#          `solari_lights` and `solari_path` with DENOISER in "none fallback" (the raw frame
#          and the lit one), frame 136 alone, the mean of frames 121-136 and the mean of
#          frames 137-392 (RUNS), `solari compare` against it. $OUT/glossy_error.csv.
# Usage: bash benches/results/glossy_hits_2026-12-07/run.sh time|error|both
set -u
source benches/results/device_env.sh
unpack_bins
for m in lights path; do
  printf '#!/bin/sh\nexec /root/bins/solari "$@" --gi-glossy-hits %s\n' $m > /root/bins/solari_$m
  chmod +x /root/bins/solari_$m
done
mkdir -p "$OUT"
time_phase() {
  local bins="solari_base solari solari_lights solari_path" r=/root/ab_time
  RESULTS=$r BINS="$bins" FLAGS="--denoiser fallback" REPS=${REPS:-2} FRAMES=300 BVH_SCENES=" " \
    SCENES="${SCENES:-cornell_box sun_boxes many_lights interior metal_rough_spheres emissive_strength_test furnace_uniform furnace_sphere}" \
    bash benches/results/ab_passes_h200.sh > "$OUT/time_log.txt" 2>&1
  mv "$OUT/ab.tar.gz" "$OUT/time.tar.gz"; rm -f "$OUT/ab_table.txt"
  python3 benches/results/memory_scratch_2026-11-26/ab_variants.py "$r" "$bins" \
    | tee "$OUT/time_table.txt"
}
error_phase() {
  local R=/root/gerr
  mkdir -p "$R"
  echo "scene,binary,denoiser,frames,mean_of,rel_mse,rmse,flip,mean_ratio,reference_noise,rel_mse_excess" \
    > "$OUT/glossy_error.csv"
  for s in ${ERROR_SCENES:-sun_boxes interior metal_rough_spheres}; do
    f=$(scene_file "$s")
    echo "== $s reference $(date -u +%T)" >&2
    /root/bins/solari render "$f" --mode reference --spp "${SPP:-1024}" --size 960x540 \
      --out "$R/${s}_ref.exr" --variance-out "$R/${s}_var.exr" > /dev/null 2>&1
    for d in none fallback; do
      for b in solari solari_lights solari_path; do
        for run in ${RUNS:-136:1 136:16 392:256}; do
          frames=${run%%:*} m=${run#*:}
          n="${s}_${b}_${d}_f${frames}_mean$m"
          /root/bins/$b render "$f" --mode realtime --denoiser $d --frames $frames --mean-of $m \
            --size 960x540 --out "$R/$n.exr" --json > "$R/$n.json" 2> "$R/$n.log"
          /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref.exr" \
            --reference-variance "$R/${s}_var.exr" --json > "$R/$n.compare.json"
          python3 - "$R/$n.compare.json" "$s" "$b" "$d" "$frames" "$m" >> "$OUT/glossy_error.csv" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
a = d.get("all", d)
n = (d.get("reference_noise") or {}).get("all") or {}
print(",".join(sys.argv[2:7] + [str(a.get(k)) for k in ("rel_mse", "rmse", "flip", "mean_ratio")]
               + [str(n.get(k)) for k in ("rel_mse", "rel_mse_excess")]))
PY
          rm -f "$R/$n.exr"
        done
      done
    done
    rm -f "$R/${s}_ref.exr" "$R/${s}_var.exr"
  done
  tar czf "$OUT/glossy_error.tar.gz" -C "$R" .
  cat "$OUT/glossy_error.csv"
}
case "${1:-}" in
  time) time_phase ;;
  error) error_phase ;;
  both) time_phase; error_phase ;;
  *) echo "usage: $0 time|error|both" >&2; exit 2 ;;
esac
