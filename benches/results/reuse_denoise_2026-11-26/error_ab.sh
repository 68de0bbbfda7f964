#!/usr/bin/env bash
# Error of two binaries (.dev/bins.tar.xz: solari_base, solari) against one full-bounce
# reference per scene, as gi_h200.sh's error phase measures it: 960x540, the last frame
# (mean1) and the mean of 16 frames (mean16) after 120, fallback denoiser, against
# `--mode reference --spp $SPP`. For changes that should leave the image's error where it
# was (re-ordered arithmetic, rays skipped where their answer cannot matter).
# Usage: bash benches/results/reuse_denoise_2026-11-26/error_ab.sh  (SCENES, MODES, SPP
# override; modes as in gi_h200.sh). Results: $OUT/error_ab.tar.gz, $OUT/error_ab.csv.
set -u
source benches/results/device_env.sh
unpack_bins
R=${RESULTS:-/root/error_ab}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box interior}
MODES=${MODES:-path+spec restir+spec}
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
cp .dev/SOLARI_COMMIT "$R/" 2>/dev/null
flags() {
  local parts spec=off; IFS=+ read -ra parts <<< "$1"
  echo "--gi ${parts[0]}"
  for p in "${parts[@]:1}"; do
    case $p in spec) spec=on ;; nodi) echo "--di-reuse none" ;;
      *) echo "unknown mode suffix +$p" >&2; exit 2 ;; esac
  done
  echo "--specular-gi $spec"
}
echo "scene,mode,binary,frames,rel_mse,rmse,flip,mean_ratio" > "$OUT/error_ab.csv"
for s in $SCENES; do
  f=$(scene_file "$s")
  echo "== $s reference $(date -u +%T)" >&2
  /root/bins/solari render "$f" --mode reference --spp "$SPP" --size 960x540 \
    --out "$R/${s}_ref.exr" --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  for g in $MODES; do
    for b in solari_base solari; do
      for m in 1 16; do
        n="${s}_${g}_${b}_mean$m"
        /root/bins/$b render "$f" --mode realtime $(flags "$g") --denoiser fallback \
          --frames 136 --mean-of $m --size 960x540 --json --out "$R/$n.exr" > "$R/$n.json" 2> "$R/$n.log"
        /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref.exr" --json > "$R/$n.compare.json" 2>> "$R/$n.log"
        python3 - "$R/$n.compare.json" "$s" "$g" "$b" "$m" >> "$OUT/error_ab.csv" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
a = c.get("all", c)
print(",".join(sys.argv[2:6] + [str(a.get(k)) for k in ("rel_mse", "rmse", "flip", "mean_ratio")]))
PY
        rm -f "$R/$n.exr"
      done
    done
  done
  rm -f "$R/${s}_ref.exr"
done
tar czf "$OUT/error_ab.tar.gz" -C "$R" --exclude='*.exr' .
cat "$OUT/error_ab.csv"
