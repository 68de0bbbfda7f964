#!/usr/bin/env bash
# Which GI mode by default, measured again now that ReSTIR GI runs at a quarter rate
# (forty-fourth session), on the device (H200). Carry .gl, .dev/bins.tar.xz and
# .dev/SOLARI_COMMIT. /root/bins holds `solari` (the commit under test) and wrappers
# `exec /root/bins/solari "$@" FLAGS` (README: which flags each adds).
#   time:  restir_half_2026-11-27/run.sh time over $BINS with `--denoiser fallback`, $SCENES,
#          1920x1080, 300 frames, two interleaved reps.
#   still: per scene in $SCENES, full-bounce references at 1024 and 4096 spp (960x540; the
#          tracer's samples are nested, so the two differ by 3/4 of the 1024-spp image's
#          noise: the floor that noise puts under every relMSE against a 1024-spp
#          reference), then each of $BINS with the fallback denoiser at the frames:mean-of
#          pairs in $RUNS and each of $RAW_BINS with `--denoiser none` at $RAW_RUNS, every
#          image compared with the 4096-spp reference. Table: $OUT/still.csv.
#   orbit: per scene in $SCENES and frame in $FRAMES (default 32 96) of the orbit camera,
#          references of that frame at 1024 and 4096 spp (the floor, as in still), then each
#          of $BINS with the fallback denoiser, compared with the 4096-spp reference.
#          Table: $OUT/orbit.csv.
#   noise: per scene in $SCENES, references at 1024 and 4096 spp with their variance
#          (`--variance-out`), then each of $BINS with the fallback denoiser (mean of frames
#          121-136, still camera) compared with both, the reference's noise taken out
#          (`compare --reference-variance`). Table: $OUT/noise.csv.
#   grid:  automatic quality's still rows again: per scene in $SCENES, a 1024-spp reference
#          with its variance, then each grid setting in $SETTINGS (default all 24, flags as
#          quality_h200.sh gives them) rendered to frame 136 with the fallback denoiser and
#          compared with it, the noise term beside (`compare --reference-variance`).
#          Table: $OUT/grid.csv.
# Usage: BINS="..." SCENES="..." bash benches/results/gi_default_2026-11-29/run.sh time|still|orbit|noise|grid
set -u
source benches/results/device_env.sh
row() { # compare JSON, then the row's leading fields
  local j=$1; shift
  python3 -c 'import json,sys; a=json.load(open(sys.argv[1]))["all"]; print(",".join(sys.argv[2:]+[str(a[k]) for k in ("rel_mse","rmse","flip","mean_ratio")]))' "$j" "$@"
}
case "${1:-}" in
  time)
    TAG=${TAG:-time} FLAGS="--denoiser fallback" bash benches/results/restir_half_2026-11-27/run.sh time ;;
  orbit)
    unpack_bins; nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
    R=/root/orbit; mkdir -p "$R" "$OUT"
    echo "scene,binary,frame,rel_mse,rmse,flip,mean_ratio" > "$OUT/orbit.csv"
    for s in ${SCENES:-cornell_box sun_boxes many_lights interior}; do
      f=$(scene_file "$s")
      for n in ${FRAMES:-32 96}; do
        for spp in 1024 4096; do
          /usr/bin/time -f "$s ref $n $spp: %e s" /root/bins/solari render "$f" --mode reference \
            --camera-path orbit --frames "$n" --spp $spp --size 960x540 --out "$R/${s}_ref${n}_$spp.exr" \
            > /dev/null 2>> "$OUT/orbit_log.txt"
        done
        /root/bins/solari compare "$R/${s}_ref${n}_1024.exr" "$R/${s}_ref${n}_4096.exr" --json > "$R/${s}_${n}_floor.json"
        row "$R/${s}_${n}_floor.json" "$s" ref1024 "$n" >> "$OUT/orbit.csv"
        for b in ${BINS:-solari}; do
          /root/bins/$b render "$f" --mode realtime --camera-path orbit --denoiser fallback --frames "$n" \
            --size 960x540 --out "$R/${s}_${b}_$n.exr" > "$R/${s}_${b}_$n.log" 2>&1
          /root/bins/solari compare "$R/${s}_${b}_$n.exr" "$R/${s}_ref${n}_4096.exr" --json > "$R/${s}_${b}_$n.compare.json"
          row "$R/${s}_${b}_$n.compare.json" "$s" "$b" "$n" >> "$OUT/orbit.csv"
          rm -f "$R/${s}_${b}_$n.exr"
        done
        rm -f "$R/${s}"_ref${n}_*.exr
      done
    done
    tar czf "$OUT/orbit.tar.gz" -C "$R" .
    cat "$OUT/orbit.csv" ;;
  still)
    unpack_bins
    R=/root/still; mkdir -p "$R" "$OUT"
    nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
    echo "scene,binary,denoiser,frames,mean_of,rel_mse,rmse,flip,mean_ratio" > "$OUT/still.csv"
    for s in ${SCENES:-cornell_box sun_boxes many_lights interior}; do
      f=$(scene_file "$s")
      for spp in 1024 4096; do
        echo "== $s reference $spp $(date -u +%T)" >&2
        /usr/bin/time -f "$s ref $spp: %e s" /root/bins/solari render "$f" --mode reference \
          --spp $spp --size 960x540 --out "$R/${s}_ref$spp.exr" > /dev/null 2>> "$OUT/still_log.txt"
      done
      /root/bins/solari compare "$R/${s}_ref1024.exr" "$R/${s}_ref4096.exr" --json > "$R/${s}_floor.json"
      row "$R/${s}_floor.json" "$s" ref1024 reference 0 1 >> "$OUT/still.csv"
      for mode in fallback none; do
        if [ $mode = fallback ]; then bins=${BINS:-solari}; runs=${RUNS:-8:1 136:1 136:16}
        else bins=${RAW_BINS:-}; runs=${RAW_RUNS:-136:1}; fi
        for b in $bins; do
          for run in $runs; do
            frames=${run%%:*} m=${run#*:}
            n="${s}_${b}_${mode}_f${frames}_mean$m"
            echo "== $n $(date -u +%T)" >&2
            /root/bins/$b render "$f" --mode realtime --denoiser $mode --frames $frames --mean-of $m \
              --size 960x540 --out "$R/$n.exr" > "$R/$n.log" 2>&1
            /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref4096.exr" --json > "$R/$n.compare.json"
            row "$R/$n.compare.json" "$s" "$b" "$mode" "$frames" "$m" >> "$OUT/still.csv"
            rm -f "$R/$n.exr"
          done
        done
      done
      rm -f "$R/${s}"_ref*.exr
    done
    tar czf "$OUT/still.tar.gz" -C "$R" .
    cat "$OUT/still.csv" ;;
  noise)
    unpack_bins
    R=/root/noise; mkdir -p "$R" "$OUT"
    nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
    echo "scene,binary,reference_spp,rel_mse,noise_rel_mse,rel_mse_excess,rmse,rmse_excess,mean_ratio" > "$OUT/noise.csv"
    for s in ${SCENES:-cornell_box sun_boxes many_lights interior}; do
      f=$(scene_file "$s")
      for spp in 1024 4096; do
        /usr/bin/time -f "$s ref $spp: %e s" /root/bins/solari render "$f" --mode reference --spp $spp \
          --size 960x540 --out "$R/${s}_ref$spp.exr" --variance-out "$R/${s}_var$spp.exr" \
          > /dev/null 2>> "$OUT/noise_log.txt"
      done
      for b in ${BINS:-solari}; do
        n="${s}_$b"
        /root/bins/$b render "$f" --mode realtime --denoiser fallback --frames 136 --mean-of 16 \
          --size 960x540 --out "$R/$n.exr" > "$R/$n.log" 2>&1
        for spp in 1024 4096; do
          /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref$spp.exr" --reference-variance "$R/${s}_var$spp.exr" \
            --json > "$R/${n}_$spp.compare.json"
          python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); a=d["all"]; n=d["reference_noise"]["all"]; print(",".join(sys.argv[2:]+[str(x) for x in (a["rel_mse"],n["rel_mse"],n["rel_mse_excess"],a["rmse"],n["rmse_excess"],a["mean_ratio"])]))' \
            "$R/${n}_$spp.compare.json" "$s" "$b" $spp >> "$OUT/noise.csv"
        done
        rm -f "$R/$n.exr"
      done
      rm -f "$R/${s}"_ref*.exr "$R/${s}"_var*.exr
    done
    tar czf "$OUT/noise.tar.gz" -C "$R" .
    cat "$OUT/noise.csv" ;;
  grid)
    unpack_bins
    R=/root/grid; mkdir -p "$R" "$OUT"
    nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
    # quality_h200.sh's grid and flags.
    all=""; for sc in 50 67 100 aa; do for g in cache path restir; do all="$all $sc-$g $sc-$g-nodi"; done; done
    gflags() {
      local parts; IFS=- read -ra parts <<< "$1"
      case ${parts[0]} in 50) echo "--internal-scale 0.5" ;; 67) echo "--internal-scale 0.67" ;;
        100) echo "--antialias off" ;; aa) echo "--antialias on" ;; esac
      case ${parts[1]} in cache) echo "--gi cache --specular-gi off" ;;
        *) echo "--gi ${parts[1]} --specular-gi on" ;; esac
      [ "${parts[2]:-}" = nodi ] && echo "--di-reuse none"
      true
    }
    echo "scene,setting,rel_mse,reference_noise,rel_mse_excess,mean_ratio" > "$OUT/grid.csv"
    for s in ${SCENES:-interior many_lights}; do
      f=$(scene_file "$s")
      /usr/bin/time -f "$s ref: %e s" /root/bins/solari render "$f" --mode reference --spp 1024 \
        --size 960x540 --out "$R/${s}_ref.exr" --variance-out "$R/${s}_var.exr" > /dev/null 2>> "$OUT/grid_log.txt"
      for g in ${SETTINGS:-$all}; do
        n="${s}_$g"
        /root/bins/solari render "$f" --mode realtime --denoiser fallback --frames 136 $(gflags "$g") \
          --size 960x540 --out "$R/$n.exr" > "$R/$n.log" 2>&1
        /root/bins/solari compare "$R/$n.exr" "$R/${s}_ref.exr" --reference-variance "$R/${s}_var.exr" \
          --json > "$R/$n.compare.json"
        python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); a=d["all"]; n=d["reference_noise"]["all"]; print(",".join(sys.argv[2:]+[str(x) for x in (a["rel_mse"],n["rel_mse"],n["rel_mse_excess"],a["mean_ratio"])]))' \
          "$R/$n.compare.json" "$s" "$g" >> "$OUT/grid.csv"
        rm -f "$R/$n.exr"
      done
      rm -f "$R/${s}"_ref.exr "$R/${s}"_var.exr
    done
    tar czf "$OUT/grid.tar.gz" -C "$R" .
    cat "$OUT/grid.csv" ;;
  *) echo "usage: $0 time|still|orbit|noise|grid" >&2; exit 2 ;;
esac
