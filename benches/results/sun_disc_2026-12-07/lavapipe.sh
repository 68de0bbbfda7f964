#!/usr/bin/env bash
# run.sh's measurement on this workstation's lavapipe, at a smaller size: the reference with
# a sun's disc found by BRDF rays (NEW, f2ea8fe's `solari`) against the one without (BASE,
# e22aa5d's), and each binary's lit frame against the new reference.
# Usage: BASE=path/to/old/solari NEW=target/release/solari bash benches/results/sun_disc_2026-12-07/lavapipe.sh
# (SCENES, SPP, SIZE override; results in $OUT, default /tmp/sun_disc).
set -u
OUT=${OUT:-/tmp/sun_disc}
R=$OUT/work
mkdir -p "$R"
source benches/results/sun_disc_2026-12-07/row.sh
echo "scene,what,rel_mse,rmse,flip,mean_ratio,reference_noise,rel_mse_excess" > "$OUT/sun_disc.csv"
for s in ${SCENES:-sun_boxes interior}; do
  f=$(ls crates/solari-testdata/scenes/"$s"/*.gltf | head -n 1)
  for b in base new; do
    bin=$BASE; [ $b = new ] && bin=$NEW
    echo "== $s reference $b $(date -u +%T)" >&2
    "$bin" render "$f" --mode reference --spp "${SPP:-512}" --size "${SIZE:-320x180}" \
      --out "$R/${s}_$b.exr" --variance-out "$R/${s}_${b}_var.exr" > /dev/null 2>&1
  done
  "$NEW" compare "$R/${s}_new.exr" "$R/${s}_base.exr" --reference-variance "$R/${s}_base_var.exr" \
    --json > "$R/${s}_ref_shift.json"
  row "$s" "new reference against old" "$R/${s}_ref_shift.json" >> "$OUT/sun_disc.csv"
  for b in base new; do
    bin=$BASE; [ $b = new ] && bin=$NEW
    echo "== $s realtime $b $(date -u +%T)" >&2
    n="${s}_${b}_mean16"
    "$bin" render "$f" --mode realtime --denoiser fallback --frames 136 --mean-of 16 \
      --size "${SIZE:-320x180}" --out "$R/$n.exr" --json > "$R/$n.json" 2> "$R/$n.log"
    "$NEW" compare "$R/$n.exr" "$R/${s}_new.exr" --reference-variance "$R/${s}_new_var.exr" \
      --json > "$R/$n.compare.json"
    row "$s" "$b lit mean of 16 against the new reference" "$R/$n.compare.json" >> "$OUT/sun_disc.csv"
  done
done
cat "$OUT/sun_disc.csv"
