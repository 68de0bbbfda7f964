#!/usr/bin/env bash
# Issue 20 item 2 (automatic quality) on the H200 (device tool): the full sweep that auto
# quality is judged against, and auto's own picks.
#   time:  every setting of the grid (SETTINGS) at 1920x1080, `render --mode realtime
#          --denoiser fallback --frames 200 --json` (GPU ms per frame: the sum of the passes);
#   error: the same settings at 960x540 (a quarter of the pixels, so `compare` stays quick;
#          ERROR_SIZE=1920x1080 measures at the output size): frame 136 of a still camera
#          against a full-bounce reference (--spp $SPP);
#   orbit: the same settings and size along the orbit camera (a moving camera): frames
#          ORBIT_FRAMES (default "32 96"), each against a reference of that frame;
#   auto:  `render --quality auto --budget-ms B` at 1920x1080 for B in BUDGETS: the setting
#          it picks (its JSON) and that setting's own frame time.
# A setting is SCALE-GI[-nodi]: SCALE 50, 67 (internal scale 0.5, 0.67 with the temporal
# upscaler; any other two digits 50-99 too, as 0.NN: settings off the grid), 100 (native)
# or aa (native, jittered + upscaler); GI cache (specular GI off),
# path or restir (specular GI on); -nodi: ReSTIR DI without reuse.
# The time and error phases are sweep_phases.sh's. Carry .gl, .dev/bins.tar.xz (stripped `solari`)
# and .dev/SOLARI_COMMIT; scenes come from
# crates/solari-testdata. Usage: PHASES="time error auto" bash benches/results/quality_h200.sh
# (SCENES, SETTINGS, BUDGETS, SPP, ORBIT_FRAMES, QUALITY_TABLE override). Results: $OUT/quality_h200.tar.gz and
# $OUT/quality_table.csv (benches/results/quality_table.py).
set -u
source benches/results/device_env.sh
unpack_bins
BIN=${SOLARI_BIN:-/root/bins/solari}
R=${RESULTS:-/root/quality}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
all=""
for s in 50 67 100 aa; do for g in cache path restir; do all="$all $s-$g $s-$g-nodi"; done; done
SETTINGS=${SETTINGS:-$all}
BUDGETS=${BUDGETS:-4 8 16}
PHASES=${PHASES:-time error auto}
# QUALITY_TABLE=FILE.csv: auto reads this table instead of the one built into the binary.
TABLE=${QUALITY_TABLE:+--quality-table $QUALITY_TABLE}
mkdir -p "$R" "$OUT"
flags() {
  local parts; IFS=- read -ra parts <<< "$1"
  case ${parts[0]} in 50) echo "--internal-scale 0.5" ;; 67) echo "--internal-scale 0.67" ;;
    [5-9][0-9]) echo "--internal-scale 0.${parts[0]}" ;;
    100) echo "--antialias off" ;; aa) echo "--antialias on" ;; *) echo "bad scale in $1" >&2; exit 2 ;; esac
  case ${parts[1]} in cache) echo "--gi cache --specular-gi off" ;;
    path|restir) echo "--gi ${parts[1]} --specular-gi on" ;; *) echo "bad GI in $1" >&2; exit 2 ;; esac
  [ "${parts[2]:-}" = nodi ] && echo "--di-reuse none"
  true
}
source benches/results/sweep_phases.sh
sweep_describe
[[ " $PHASES " == *" time "* ]] && sweep_time
[[ " $PHASES " == *" error "* ]] && sweep_error
[[ " $PHASES " == *" orbit "* ]] && sweep_orbit
if [[ " $PHASES " == *" auto "* ]]; then
  for s in $SCENES; do
    f=$(scene_file "$s")
    for b in $BUDGETS; do
      echo "== $s auto $b ms $(date -u +%T)" >&2
      $BIN render "$f" --mode realtime --quality auto --budget-ms "$b" --denoiser fallback $TABLE \
        --frames 200 --size 1920x1080 --json --out "$R/x.png" > "$R/${s}_auto${b}.json" \
        2> "$R/${s}_auto${b}.log"
    done
  done
fi
rm -f "$R/x.png"
tar czf "$OUT/quality_h200.tar.gz" -C "$R" --exclude='*.exr' .
python3 benches/results/quality_table.py "$R" > "$OUT/quality_table.csv"; cat "$OUT/quality_table.csv"
