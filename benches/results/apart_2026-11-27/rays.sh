#!/usr/bin/env bash
# Thirty-first session: bench-rays with each workgroup's hemisphere rays regrouped by direction
# (experiments/ray_sort_env.patch, SOLARI_EXP_RAY_SORT=0..3) against the shipped kernel, on
# the device (H100/H200), interleaved reps on one warm machine. Carry .gl,
# .dev/bins.tar.xz (holding `solari_exp`, the patched build) and .dev/SOLARI_COMMIT.
#   MODES (default "none 0 1 2 3"; none = the shipped kernel), SCENES, REPS (default 2),
#   FRAMES (default 200), PRESET (default medium). Writes $OUT/rays.csv and the JSON lines.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
MODES=${MODES:-none 0 1 2 3}
SCENES=${SCENES:-interior many_lights sun_boxes}
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.txt" 2>/dev/null
for rep in $(seq 1 "${REPS:-2}"); do
  for s in $SCENES; do
    for m in $MODES; do
      if [ "$m" = none ]; then unset SOLARI_EXP_RAY_SORT; else export SOLARI_EXP_RAY_SORT=$m; fi
      /root/bins/solari_exp bench-rays "$(scene_file "$s")" --tracer software \
        --presets "${PRESET:-medium}" --frames "${FRAMES:-200}" --json 2>> "$OUT/rays_err.txt" \
        | tail -n 1 | sed "s/^{/{\"mode\":\"$m\",\"rep\":$rep,\"name\":\"$s\",/" >> "$OUT/rays.jsonl"
    done
  done
done
unset SOLARI_EXP_RAY_SORT
python3 - "$OUT/rays.jsonl" <<'PY' | tee "$OUT/rays_table.txt"
import json, sys, statistics as st
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
by = {}
for r in rows:
    by.setdefault((r["name"], r["mode"]), []).append(r)
for (s, m), rs in sorted(by.items()):
    ao = st.median(r["ao_ms"] for r in rs)
    pr = st.median(r["primary_ms"] for r in rs)
    print(f"{s:12s} mode {m:4s} primary {pr:.4f} ms  primary+AO {ao:.4f} ms  AO rays {rs[0]['ao_rays']}  "
          f"{st.median(r['ao_grays_per_s'] for r in rs):.3f} Grays/s  reps {len(rs)}")
PY
