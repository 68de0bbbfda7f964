#!/usr/bin/env bash
# GI's glossy hits on this workstation's lavapipe (2 cores; errors only: lavapipe's timings
# mean nothing), fifty-second session. One binary, SOLARI (default target/release/solari, built
# from the change), with `--gi-glossy-hits` at each of GLOSSY ("cache lights path"; cache is
# the default, which compiles the glossy-hit code out of the pass).
#   SCENES (sun_boxes metal_rough_spheres interior cornell_box), SIZE (320x180), SPP (256),
#   RUNS (frames:mean-of pairs of the raw indirect view, "136:16 392:256"),
#   WORK (/tmp/glossy_hits).
# Per scene two references at pixel centres: full-bounce (lit) and `--min-bounces 2`
# (indirect). Per setting:
#   indirect raw (`--view indirect --denoiser none`): mean of frames 121-136 and of 137-392
#     against the indirect reference;
#   lit (defaults: path GI, fallback denoiser, `--antialias off` so that pixel centres are
#     what is shaded): frame 136 alone against the full reference.
# Prints one CSV line per run: scene,glossy,what,mean_ratio,rel_mse_excess (relMSE without
# the reference's own noise).
set -u
SCENES=${SCENES:-sun_boxes metal_rough_spheres interior cornell_box}
SIZE=${SIZE:-320x180}; SPP=${SPP:-256}; GLOSSY=${GLOSSY:-cache lights path}
S=${SOLARI:-target/release/solari}
W=${WORK:-/tmp/glossy_hits}; mkdir -p "$W"
cmp() {
  $S compare "$1" "$2" --reference-variance "$3" --json | python3 -c \
    'import json,sys; d=json.load(sys.stdin); print("%.4f,%.6f" % (d["all"]["mean_ratio"], d["reference_noise"]["all"]["rel_mse_excess"]))'
}
echo "scene,glossy,what,mean_ratio,rel_mse_excess"
for s in $SCENES; do
  I=$(ls crates/solari-testdata/scenes/$s/*.gltf | head -n 1)
  for kind in full indirect; do
    r=$W/ref_${s}_${SIZE}_${SPP}_$kind
    extra=""; [ $kind = indirect ] && extra="--min-bounces 2"
    # shellcheck disable=SC2086
    [ -f "$r.exr" ] || $S render "$I" --mode reference $extra --spp "$SPP" --pixel-centre \
      --size "$SIZE" --out "$r.exr" --variance-out "$r.var.exr" > /dev/null 2>&1
  done
  ri=$W/ref_${s}_${SIZE}_${SPP}_indirect; rf=$W/ref_${s}_${SIZE}_${SPP}_full
  for g in $GLOSSY; do
    for run in ${RUNS:-136:16 392:256}; do
      f=${run%%:*} m=${run#*:}
      o=$W/${s}_${SIZE}_${g}_ind_f${f}_m$m.exr
      $S render "$I" --mode realtime --view indirect --denoiser none --size "$SIZE" \
        --frames "$f" --mean-of "$m" --gi-glossy-hits "$g" --out "$o" > /dev/null 2>&1 \
        || { echo "$s,$g,indirect f$f m$m,failed"; continue; }
      echo "$s,$g,indirect raw mean of $m to frame $f,$(cmp "$o" "$ri.exr" "$ri.var.exr")"
    done
    o=$W/${s}_${SIZE}_${g}_lit_f136.exr
    $S render "$I" --mode realtime --antialias off --size "$SIZE" --frames 136 \
      --gi-glossy-hits "$g" --out "$o" > /dev/null 2>&1 || { echo "$s,$g,lit,failed"; continue; }
    echo "$s,$g,lit frame 136 (fallback denoiser),$(cmp "$o" "$rf.exr" "$rf.var.exr")"
  done
done
