#!/usr/bin/env bash
# Error A/B of two solari binaries on the device: per scene, a 1024-spp full-bounce reference
# at 960x540, then with each binary (`solari_base`, `solari` in the carried
# .dev/bins.tar.xz) the default real-time settings, 136 frames, the last frame and the mean
# of the last 16, denoised (fallback) and raw (--denoiser none), each compared with the
# reference. Lines go to $OUT/err.txt. Usage: bash benches/results/denoise_err_ab_h200.sh
set -u
source benches/results/device_env.sh
unpack_bins
R=/root/err; mkdir -p $R $OUT
for s in cornell_box sun_boxes many_lights interior; do
  f=$(scene_file "$s")
  /root/bins/solari render "$f" --mode reference --spp 1024 --size 960x540 --out "$R/${s}_ref.exr" > /dev/null 2>&1
  for b in solari_base solari; do
    for m in 1 16; do
      n="${s}_${b}_mean$m"
      /root/bins/$b render "$f" --mode realtime --denoiser fallback --frames 136 --mean-of $m --size 960x540 --json --out "$R/$n.exr" > "$R/$n.json" 2> "$R/$n.log"
      /root/bins/$b render "$f" --mode realtime --denoiser none --frames 136 --mean-of $m --size 960x540 --json --out "$R/${n}_raw.exr" > /dev/null 2>&1
      c=$(/root/bins/solari compare "$R/$n.exr" "$R/${s}_ref.exr" --json)
      r=$(/root/bins/solari compare "$R/${n}_raw.exr" "$R/${s}_ref.exr" --json)
      echo "$s $b mean$m denoised $c raw $r" | tee -a $OUT/err.txt
    done
  done
done
