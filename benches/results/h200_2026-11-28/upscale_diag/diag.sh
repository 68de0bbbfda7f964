set -u
source benches/results/device_env.sh
unpack_bins
B=/root/bins/solari; f=$(scene_file interior); mkdir -p $OUT
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for n in 96 32; do
  $B render "$f" --mode reference --camera-path orbit --frames $n --spp 1024 --size 960x540 --out $OUT/ref_$n.exr > /dev/null 2>&1
  C="--mode realtime --camera-path orbit --denoiser fallback --frames $n --size 960x540 --gi path --specular-gi on --di-reuse none"
  $B render "$f" $C --antialias off --out $OUT/n100_$n.exr > /dev/null 2>&1
  $B render "$f" $C --internal-scale 0.67 --out $OUT/n67_$n.exr > /dev/null 2>&1
  $B render "$f" $C --antialias off --view gbuffer-depth --out $OUT/depth_$n.exr > /dev/null 2>&1
  for v in n100 n67; do echo "$v $n $($B compare $OUT/${v}_$n.exr $OUT/ref_$n.exr --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["all"]["rel_mse"])')"; done
done
ls -la $OUT
