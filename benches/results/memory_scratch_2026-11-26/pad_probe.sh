source benches/results/device_env.sh
unpack_bins
R=/root/pad; mkdir -p $R $OUT
f=$(scene_file interior)
for b in solari_base solari; do /root/bins/$b render "$f" --mode realtime --denoiser fallback --frames 600 --size 1920x1080 --out $R/x.png > /dev/null 2>&1; done
for rep in 1 2; do
  for v in base:0 new:0 pad:1048576 pad:4194560 pad:67108864; do
    b=${v%%:*}; p=${v#*:}
    bin=/root/bins/solari; [ $b = base ] && bin=/root/bins/solari_base
    [ $b = pad ] && bin=/root/bins/solari_pad
    XPAD=$p $bin render "$f" --mode realtime --denoiser fallback --frames 300 --size 1920x1080 --json --out $R/x.png > $R/pad_${b}_${p}_$rep.json 2>/dev/null
  done
done
cd $R && for j in pad_*.json; do python3 -c "
import json,sys; j=json.load(open('$j')); p=j['passes']
print('$j', *(f\"{k}={p[k]['mean_ms']:.4f}\" for k in ['gi_spatial_shade','specular_gi','denoise_atrous','di_spatial_shade']), f\"frame={j['gpu_frame_ms']:.4f}\")"; done | tee $OUT/pad.txt
