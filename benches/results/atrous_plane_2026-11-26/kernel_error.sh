#!/usr/bin/env bash
# Error of several solari binaries (or wrapper scripts) against one full-bounce reference per
# scene, as gi_h200.sh's error phase measures it (960x540; `solari compare`): BINS names them
# under /root/bins (default "solari"), SCENES and SPP as there. Defaults otherwise, with the
# fallback denoiser. RUNS lists frames:mean-of pairs (default "136:1 136:16": the last frame
# and the mean of 16 after 120, as gi_h200.sh; "1:1 8:1" are the first frame and the eighth,
# whose histories are young, so the spatial filter does most of the work). Table:
# $OUT/kernel_error.csv. It does what reuse_denoise_2026-11-26/error_ab.sh did for a fixed
# pair of binaries and frame counts, with both as lists: use this one for new comparisons
# (the older one stays as the record of its session's figures). DENOISER picks the denoiser
# (default fallback; `none` for the raw frames). Since the forty-fourth session the reference
# carries its variance and the table two more columns: reference_noise (what the reference's
# own noise adds to rel_mse) and rel_mse_excess (rel_mse without it; benches/RESULTS.md, "The
# reference's own noise").
set -u
source benches/results/device_env.sh
unpack_bins
R=${RESULTS:-/root/kerr}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
BINS=${BINS:-solari}
RUNS=${RUNS:-136:1 136:16}
mkdir -p "$R" "$OUT"
echo "scene,binary,frames,mean_of,rel_mse,rmse,flip,mean_ratio,reference_noise,rel_mse_excess" > "$OUT/kernel_error.csv"
for s in $SCENES; do
  f=$(scene_file "$s")
  echo "== $s reference $(date -u +%T)" >&2
  /root/bins/solari render "$f" --mode reference --spp "$SPP" --size 960x540 \
    --out "$R/${s}_ref.exr" --variance-out "$R/${s}_var.exr" > /dev/null 2>&1
  for b in $BINS; do
    for run in $RUNS; do
      frames=${run%%:*} m=${run#*:}
      n="${s}_${b}_f${frames}_mean$m"
      /root/bins/$b render "$f" --mode realtime --denoiser "${DENOISER:-fallback}" --frames $frames --mean-of $m \
        --size 960x540 --out "$R/$n.exr" > "$R/$n.log" 2>&1
      /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref.exr" --reference-variance "$R/${s}_var.exr" \
        --json > "$R/$n.compare.json"
      python3 - "$R/$n.compare.json" "$s" "$b" "$frames" "$m" >> "$OUT/kernel_error.csv" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
a = d.get("all", d)
n = (d.get("reference_noise") or {}).get("all") or {}
print(",".join(sys.argv[2:6] + [str(a.get(k)) for k in ("rel_mse", "rmse", "flip", "mean_ratio")]
               + [str(n.get(k)) for k in ("rel_mse", "rel_mse_excess")]))
PY
      rm -f "$R/$n.exr"
    done
  done
  rm -f "$R/${s}_ref.exr" "$R/${s}_var.exr"
done
tar czf "$OUT/kernel_error.tar.gz" -C "$R" .
cat "$OUT/kernel_error.csv"
