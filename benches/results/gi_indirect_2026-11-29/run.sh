#!/usr/bin/env bash
# GI's own error: the indirect view (`render --view indirect`: the GI passes' light alone)
# against references of indirect light alone (`--mode reference --min-bounces 2`), so that
# DI's noise and bias are out of the comparison between GI modes (forty-fifth session, on the
# device: H200). Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT. /root/bins holds
# `solari` (the commit under test) and wrappers `exec /root/bins/solari "$@" FLAGS` (README).
#   indirect: per scene in $SCENES, two indirect references of $SPP paths (default 4096) at
#             960x540 with their variance: jittered (for the denoised frames, which
#             antialias) and `--pixel-centre` (for the raw frames, which do not). Then each of
#             $BINS: denoised (fallback) frame 136 and the mean of frames 121-136, raw
#             (`--denoiser none`) frame 136 and the mean of 121-136, each compared with its
#             reference with the reference's noise taken out (`compare --reference-variance`).
#             Table: $OUT/indirect.csv. SIZE and RUNS (frames:mean-of pairs) shrink it for a
#             try on lavapipe; MODES="none" KINDS="centre" measures the raw frames alone.
#   lit:      the same for the lit image against full-bounce references (no --min-bounces),
#             so that the frame as a user sees it is measured by the same binaries and
#             references of the same kind. Table: $OUT/lit.csv.
# Usage: BINS="..." SCENES="..." bash benches/results/gi_indirect_2026-11-29/run.sh indirect|lit
set -u
source benches/results/device_env.sh
case "${1:-}" in
  indirect|lit)
    phase=$1
    if [ $phase = indirect ]; then ref_flags="--min-bounces 2"; view="--view indirect"
    else ref_flags=""; view=""; fi
    unpack_bins
    R=/root/$phase; mkdir -p "$R" "$OUT"
    nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
    [ -f "$OUT/$phase.csv" ] || echo "scene,binary,denoiser,frames,mean_of,rel_mse,noise_rel_mse,rel_mse_excess,rmse,rmse_excess,mean_ratio" > "$OUT/$phase.csv"
    for s in ${SCENES:-cornell_box interior}; do
      f=$(scene_file "$s")
      for kind in ${KINDS:-jit centre}; do
        extra=""; [ $kind = centre ] && extra="--pixel-centre"
        echo "== $s reference $kind $(date -u +%T)" >&2
        /usr/bin/time -f "$s ref $kind ${SPP:-4096}: %e s" /root/bins/solari render "$f" --mode reference \
          $ref_flags --spp ${SPP:-4096} $extra --size ${SIZE:-960x540} --out "$R/${s}_$kind.exr" \
          --variance-out "$R/${s}_${kind}_var.exr" --json > "$R/${s}_$kind.json" 2>> "$OUT/${phase}_log.txt"
      done
      for b in ${BINS:-p}; do
        for mode in ${MODES:-fallback none}; do
          kind=jit; [ $mode = none ] && kind=centre
          for run in ${RUNS:-136:1 136:16}; do
            frames=${run%%:*} m=${run#*:}
            n="${s}_${b}_${mode}_f${frames}_mean$m"
            echo "== $n $(date -u +%T)" >&2
            /root/bins/$b render "$f" --mode realtime $view --denoiser $mode --frames $frames \
              --mean-of $m --size ${SIZE:-960x540} --out "$R/$n.exr" > "$R/$n.log" 2>&1
            /root/bins/solari compare "$R/$n.exr" "$R/${s}_$kind.exr" \
              --reference-variance "$R/${s}_${kind}_var.exr" --json > "$R/$n.compare.json"
            python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); a=d["all"]; n=d["reference_noise"]["all"]; print(",".join(sys.argv[2:]+[str(x) for x in (a["rel_mse"],n["rel_mse"],n["rel_mse_excess"],a["rmse"],n["rmse_excess"],a["mean_ratio"])]))' \
              "$R/$n.compare.json" "$s" "$b" "$mode" "$frames" "$m" >> "$OUT/$phase.csv"
            rm -f "$R/$n.exr"
          done
        done
      done
      rm -f "$R/${s}"_*.exr
    done
    tar czf "$OUT/$phase.tar.gz" -C "$R" .
    cat "$OUT/$phase.csv" ;;
  *) echo "usage: $0 indirect|lit" >&2; exit 2 ;;
esac
