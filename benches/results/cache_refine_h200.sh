#!/usr/bin/env bash
# Issue 18 item 5 on the H200 (device tool): Solari 0.19's world-cache refinements, each on
# its own and together, under plain path GI (the default: cache at the path's end) and
# cache-only GI.
#   time:  1920x1080, `render --mode realtime --denoiser fallback --frames 200 --json`;
#   error: 960x540, frame 136 of a still camera against a full-bounce reference (--spp $SPP).
# A setting is GI-VARIANT[-bN]: GI path (--gi path --specular-gi on) or cache (--gi cache
# --specular-gi off); VARIANT base (finest cell 0.25 m, leak rule on, hard LOD: the defaults
# until 0045f68), c015 (finest cell 0.15 m), noleak (leak rule off), soft (blended LOD
# transitions), s19 (0.15 m and blended transitions, the leak rule on: Solari 0.19's set);
# bN: an update budget of N thousand cells (default 40). Every knob is given explicitly and
# the table pinned to 2^18 slots, as the measured runs had them, so later changes to the
# defaults do not change what a setting means.
# The time and error phases are sweep_phases.sh's. Carry .gl, .dev/bins.tar.xz (stripped `solari`)
# and .dev/SOLARI_COMMIT; scenes come from
# crates/solari-testdata. Usage: PHASES="time error" bash benches/results/cache_refine_h200.sh
# (SCENES, SETTINGS, SPP override). Results: $OUT/cache_refine_<phases>.tar.gz and
# $OUT/cache_refine_table.csv (benches/results/quality_table.py).
set -u
source benches/results/device_env.sh
unpack_bins
BIN=${SOLARI_BIN:-/root/bins/solari}
R=${RESULTS:-/root/cache_refine}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
all=""
for g in path cache; do for v in base c015 noleak soft s19; do all="$all $g-$v"; done; done
SETTINGS=${SETTINGS:-$all}
PHASES=${PHASES:-time error}
mkdir -p "$R" "$OUT"
flags() {
  local parts; IFS=- read -ra parts <<< "$1"
  case ${parts[0]} in path) echo "--gi path --specular-gi on" ;;
    cache) echo "--gi cache --specular-gi off" ;; *) echo "bad GI in $1" >&2; exit 2 ;; esac
  local cell=0.25 leak=on soft=off budget=40
  case ${parts[1]} in base) ;; c015) cell=0.15 ;; noleak) leak=off ;; soft) soft=on ;;
    s19) cell=0.15; soft=on ;; *) echo "bad variant in $1" >&2; exit 2 ;; esac
  case ${parts[2]:-} in "") ;; b*) budget=${parts[2]#b} ;;
    *) echo "bad budget in $1" >&2; exit 2 ;; esac
  echo "--cache-cell-size $cell --cache-leak-rule $leak --cache-soft-lod $soft" \
    "--cache-budget ${budget}000 --cache-capacity 262144"
}
source benches/results/sweep_phases.sh
sweep_describe
[[ " $PHASES " == *" time "* ]] && sweep_time
[[ " $PHASES " == *" error "* ]] && sweep_error
rm -f "$R/x.png"
tar czf "$OUT/cache_refine_${PHASES// /_}.tar.gz" -C "$R" --exclude='*.exr' .
python3 benches/results/quality_table.py "$R" > "$OUT/cache_refine_table.csv"; cat "$OUT/cache_refine_table.csv"
