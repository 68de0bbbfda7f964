#!/usr/bin/env bash
# Thirty-first session: error along the orbit camera path (new cells every frame), on the
# device. For each scene and frame count in FRAMES, one full-bounce reference of that frame's
# camera (`--mode reference --camera-path orbit --frames F`, SPP, 960x540), then each of
# BINS (wrappers under /root/bins) rendered to the same frame with the fallback denoiser.
# Table: $OUT/orbit_error.csv. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
R=/root/orbit; mkdir -p "$R" "$OUT"
SPP=${SPP:-1024}
echo "scene,binary,frame,rel_mse,rmse,flip,mean_ratio" > "$OUT/orbit_error.csv"
for s in ${SCENES:-interior}; do
  f=$(scene_file "$s")
  for n in ${FRAMES:-8 32 96}; do
    /root/bins/solari render "$f" --mode reference --camera-path orbit --frames "$n" --spp "$SPP" \
      --size 960x540 --out "$R/${s}_ref_$n.exr" > /dev/null 2>&1
    for b in ${BINS:-solari}; do
      /root/bins/$b render "$f" --mode realtime --camera-path orbit --denoiser fallback --frames "$n" \
        --size 960x540 --out "$R/${s}_${b}_$n.exr" > "$R/${s}_${b}_$n.log" 2>&1
      /root/bins/solari compare "$R/${s}_${b}_$n.exr" "$R/${s}_ref_$n.exr" --json \
        | python3 -c 'import json,sys; a=json.load(sys.stdin)["all"]; print(",".join(sys.argv[1:4]+[str(a[k]) for k in ("rel_mse","rmse","flip","mean_ratio")]))' "$s" "$b" "$n" \
        >> "$OUT/orbit_error.csv"
    done
  done
done
cat "$OUT/orbit_error.csv"
