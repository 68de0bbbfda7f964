#!/usr/bin/env bash
# A sun's disc found by BRDF rays (f2ea8fe) on the shared scenes, on the device: references
# from `solari_base` (e22aa5d, the disc found by light samples alone) and `solari` (f2ea8fe),
# 2048 paths at 960x540 with their variance, the new one compared with the old (how far the
# references of every earlier table sit from the corrected one); then each binary's lit
# frame (fallback denoiser, defaults; frame 136 and the mean of frames 121-136) against the
# new reference. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
# Usage: bash benches/results/sun_disc_2026-12-07/run.sh   (SCENES, SPP override)
set -u
source benches/results/device_env.sh
unpack_bins
R=/root/sd
mkdir -p "$R" "$OUT"
source benches/results/sun_disc_2026-12-07/row.sh
echo "scene,what,rel_mse,rmse,flip,mean_ratio,reference_noise,rel_mse_excess" > "$OUT/sun_disc.csv"
for s in ${SCENES:-cornell_box sun_boxes interior}; do
  f=$(scene_file "$s")
  for b in solari_base solari; do
    echo "== $s reference $b $(date -u +%T)" >&2
    /root/bins/$b render "$f" --mode reference --spp "${SPP:-2048}" --size 960x540 \
      --out "$R/${s}_$b.exr" --variance-out "$R/${s}_${b}_var.exr" > /dev/null 2>&1
  done
  /root/bins/solari compare "$R/${s}_solari.exr" "$R/${s}_solari_base.exr" \
    --reference-variance "$R/${s}_solari_base_var.exr" --json > "$R/${s}_ref_shift.json"
  row "$s" "new reference against old" "$R/${s}_ref_shift.json" >> "$OUT/sun_disc.csv"
  for b in solari_base solari; do
    for m in 1 16; do
      n="${s}_${b}_mean$m"
      /root/bins/$b render "$f" --mode realtime --denoiser fallback --frames 136 --mean-of $m \
        --size 960x540 --out "$R/$n.exr" --json > "$R/$n.json" 2> "$R/$n.log"
      /root/bins/solari compare "$R/$n.exr" "$R/${s}_solari.exr" \
        --reference-variance "$R/${s}_solari_var.exr" --json > "$R/$n.compare.json"
      row "$s" "$b lit mean of $m against the new reference" "$R/$n.compare.json" >> "$OUT/sun_disc.csv"
    done
  done
done
tar czf "$OUT/sun_disc.tar.gz" -C "$R" --exclude='*.exr' .
cat "$OUT/sun_disc.csv"
