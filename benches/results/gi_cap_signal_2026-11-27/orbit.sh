#!/bin/bash
# usage: orbit.sh SCENE(cornell|interior) VARIANTS... ; FRAMES="8 32 96 136 200"
# References per frame are made on first use under /tmp/capx (oref_SCENE_FRAMES.exr). Images go to /tmp/capx.
cd "$(git rev-parse --show-toplevel)"  # run from anywhere in the checkout; lavapipe build: cargo build --release -p solari-app with experiments/cap_signals.patch applied
B=${B:-target/release/solari}
case $1 in
  cornell) SC=""; SIZE=128x128; SPP=1024;;
  interior) SC=../shared/scenes/interior/interior.gltf; SIZE=160x90; SPP=256;;
esac
name=$1; shift
for f in ${FRAMES:-8 32 96 136 200}; do
  REF=/tmp/capx/oref_${name}_$f.exr
  [ -f $REF ] || $B render $SC --mode reference --camera-path orbit --frames $f --spp $SPP --size $SIZE --out $REF >/dev/null 2>&1
done
for v in "$@"; do
  line="$v"
  for f in ${FRAMES:-8 32 96 136 200}; do
    REF=/tmp/capx/oref_${name}_$f.exr
    e=""; r=""; a=""; g=restir; unset SOLARI_EXP_GATE
    case $v in
      fixed) a="--gi-adaptive-cap off";;
      sample) ;;
      pixel) e="pixel";;
      ramp) r=0.1; a="--gi-adaptive-cap off";;
      gate) export SOLARI_EXP_GATE=0.1;;
      path) g=path;;
    esac
    out=/tmp/capx/o_${name}_${v}_$f.exr
    SOLARI_EXP_RAMP=$r SOLARI_EXP_CAP=$e $B render $SC --mode realtime --camera-path orbit --gi $g $a --frames $f --size $SIZE --denoiser fallback --out $out >/dev/null 2>&1 || echo FAIL
    x=$($B compare $out $REF --json | python3 -c 'import json,sys; d=json.load(sys.stdin)["all"]; print("%.4f/%.3f"%(d["rel_mse"],d["mean_ratio"]))')
    line="$line f$f=$x"
  done
  echo "$line"
done
