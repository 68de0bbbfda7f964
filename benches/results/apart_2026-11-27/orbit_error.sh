#!/usr/bin/env bash
# Thirty-first session: error along the orbit camera path (new cells every frame), on the
# device. For each scene and frame count in FRAMES, one full-bounce reference of that frame's
# camera (`--mode reference --camera-path orbit --frames F`, SPP, 960x540), then each of
# BINS (wrappers under /root/bins) rendered to the same frame with the fallback denoiser.
# Table: $OUT/orbit_error.csv (since the forty-fourth session with reference_noise, what the
# reference's own noise adds to rel_mse, and rel_mse_excess, rel_mse without it). Carry .gl,
# .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
R=/root/orbit; mkdir -p "$R" "$OUT"
SPP=${SPP:-1024}
echo "scene,binary,frame,rel_mse,rmse,flip,mean_ratio,reference_noise,rel_mse_excess" > "$OUT/orbit_error.csv"
for s in ${SCENES:-interior}; do
  f=$(scene_file "$s")
  for n in ${FRAMES:-8 32 96}; do
    /root/bins/solari render "$f" --mode reference --camera-path orbit --frames "$n" --spp "$SPP" \
      --size 960x540 --out "$R/${s}_ref_$n.exr" --variance-out "$R/${s}_var_$n.exr" > /dev/null 2>&1
    for b in ${BINS:-solari}; do
      /root/bins/$b render "$f" --mode realtime --camera-path orbit --denoiser fallback --frames "$n" \
        --size 960x540 --out "$R/${s}_${b}_$n.exr" > "$R/${s}_${b}_$n.log" 2>&1
      /root/bins/solari compare "$R/${s}_${b}_$n.exr" "$R/${s}_ref_$n.exr" \
        --reference-variance "$R/${s}_var_$n.exr" --json \
        | python3 -c 'import json,sys; d=json.load(sys.stdin); a=d["all"]; n=d["reference_noise"]["all"]; print(",".join(sys.argv[1:4]+[str(a[k]) for k in ("rel_mse","rmse","flip","mean_ratio")]+[str(n[k]) for k in ("rel_mse","rel_mse_excess")]))' "$s" "$b" "$n" \
        >> "$OUT/orbit_error.csv"
    done
  done
done
cat "$OUT/orbit_error.csv"
