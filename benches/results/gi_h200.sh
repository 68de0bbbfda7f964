#!/usr/bin/env bash
# GI modes on the H200 (device tool), one command. Issue 18, "Time against error" (first
# slice: diffuse GI, and specular GI with a mode ending in +spec; no PSR yet):
#   1. timing at 1920x1080: `solari render --mode realtime --gi MODE --denoiser fallback
#      --frames 200 --json` per scene and mode (per-pass GPU ms in the summary);
#   2. error at 960x540 (a quarter of the pixels, so `solari compare` stays quick): the
#      last frame and the mean of 16 frames (`--mean-of 16`) after 120, against a full-bounce
#      reference (`--mode reference --spp $SPP`, default bounces).
# Needs .gl, .dev/bins.tar.xz (stripped `solari` of the commit under test) and
# .dev/SOLARI_COMMIT carried; scenes come from crates/solari-testdata (runs before the
# fifteenth session read .dev/solari and .dev/scenes). Usage: bash benches/results/gi_h200.sh   (SCENES, MODES, SPP, PHASES override). A
# mode is a GI mode with optional suffixes: +spec adds specular GI (`--specular-gi on`;
# without it `--specular-gi off`, since specular GI is on by default from 5f47d02), +nodi
# runs ReSTIR DI without reuse (`--di-reuse none`), +alldi with both reuses whatever the
# scene (`--di-reuse all`; the default is `auto`), +nopsr turns primary surface
# replacement off (`--psr off`), +sN takes N GI candidates per pixel (`--gi-samples N`),
# +biased drops ReSTIR GI's unbiased spatial MIS ray (`--gi-spatial-visibility neighbour`;
# `--gi-unbiased-spatial off` before the twenty-first session), +chosen traces only the
# chosen sample's ray (`--gi-spatial-visibility chosen`), +half traces from half the pixels
# (`--gi-half-rate`), e.g.
# MODES="path path+spec path+spec+nodi path+spec+s4". PHASES="time
# error" (default both) runs either half alone, so a long sweep can span two device commands.
# Everything lands in $OUT/gi_h200.tar.gz, the table in $OUT/gi_table.csv.
set -u
source benches/results/device_env.sh
unpack_bins
BIN=${SOLARI_BIN:-/root/bins/solari}
R=${RESULTS:-/root/gi}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
MODES=${MODES:-off cache path restir}
# DENOISER=none measures the raw frames (default fallback).
DENOISER=${DENOISER:-fallback}
mkdir -p "$R" "$OUT"
PHASES=${PHASES:-time error}
# "cache+spec+nodi" -> --gi cache --specular-gi --di-reuse none
flags() {
  local parts spec=off; IFS=+ read -ra parts <<< "$1"
  echo "--gi ${parts[0]}"
  for p in "${parts[@]:1}"; do
    case $p in spec) spec=on ;; nodi) echo "--di-reuse none" ;; alldi) echo "--di-reuse all" ;; nopsr) echo "--psr off" ;;
      s[0-9]*) echo "--gi-samples ${p#s}" ;; biased) echo "--gi-spatial-visibility neighbour" ;;
      chosen) echo "--gi-spatial-visibility chosen" ;; half) echo "--gi-half-rate" ;;
      *) echo "unknown mode suffix +$p" >&2; exit 2 ;; esac
  done
  echo "--specular-gi $spec"
}
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
cp .dev/SOLARI_COMMIT "$R/" 2>/dev/null
if [[ " $PHASES " == *" time "* ]]; then
  # Warm-up: the first runs read 1.8-2x slow on the H100 (sweep_phases.sh).
  "$BIN" render "$(scene_file cornell_box)" --mode realtime --frames 600 --size 1920x1080 \
    --out "$R/x.png" > /dev/null 2>&1
fi
for s in $SCENES; do
  [[ " $PHASES " == *" time "* ]] || break
  f=$(scene_file "$s")
  for g in $MODES; do
    echo "== $s $g timing $(date -u +%T)" >&2
    "$BIN" render "$f" --mode realtime $(flags "$g") --denoiser "$DENOISER" --frames 200 \
      --size 1920x1080 --json --out "$R/x.png" > "$R/${s}_${g}_1080p.json" 2> "$R/${s}_${g}_1080p.log"
  done
done
for s in $SCENES; do
  [[ " $PHASES " == *" error "* ]] || break
  f=$(scene_file "$s")
  echo "== $s reference $(date -u +%T)" >&2
  # With its variance: the compares hold the reference's own noise (gi_table.py's
  # reference_noise column; benches/RESULTS.md, "The reference's own noise").
  "$BIN" render "$f" --mode reference --spp "$SPP" --size 960x540 --out "$R/${s}_ref.exr" \
    --variance-out "$R/${s}_var.exr" --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  for g in $MODES; do
    for m in 1 16; do
      n="${s}_${g}_mean$m"
      "$BIN" render "$f" --mode realtime $(flags "$g") --denoiser "$DENOISER" --frames 136 \
        --mean-of $m --size 960x540 --json --out "$R/$n.exr" > "$R/$n.json" 2> "$R/$n.log"
      "$BIN" compare "$R/$n.exr" "$R/${s}_ref.exr" --reference-variance "$R/${s}_var.exr" \
        --json > "$R/$n.compare.json" 2>> "$R/$n.log"
      rm -f "$R/$n.exr"
    done
  done
  rm -f "$R/${s}_ref.exr" "$R/${s}_var.exr"
done
tar czf "$OUT/gi_h200.tar.gz" -C "$R" --exclude='*.exr' --exclude='x.png' .
# The table: one CSV row per scene and mode (benches/results/gi_table.py), kept in $OUT and
# printed; plot it with `cargo run -p solari-benches --bin plot-gi -- gi_table.csv out.png`.
python3 benches/results/gi_table.py "$R" > "$OUT/gi_table.csv"; cat "$OUT/gi_table.csv"
