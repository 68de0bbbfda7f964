#!/bin/bash
# usage: probe.sh SCENE(cornell|interior) VARIANTS... ; RUNS="8:1 32:1 136:16"
# Static references as made last session (see README.md): /tmp/yf/cref.exr, /tmp/yf/iref.exr. Images go to /tmp/capx.
cd "$(git rev-parse --show-toplevel)"  # run from anywhere in the checkout; lavapipe build: cargo build --release -p solari-app with experiments/cap_signals.patch applied
B=${B:-target/release/solari}
case $1 in
  cornell) SC=""; SIZE=128x128; REF=/tmp/yf/cref.exr;;
  interior) SC=../shared/scenes/interior/interior.gltf; SIZE=160x90; REF=/tmp/yf/iref.exr;;
esac
shift
for v in "$@"; do
  for run in ${RUNS:-8:1 32:1 136:16}; do
    f=${run%%:*} m=${run#*:}
    unset SOLARI_EXP_RAMP
    case $v in
      fixed) e=""; a="--gi-adaptive-cap off";;
      sample) e=""; a="";;
      pixel) e="pixel"; a="";;
      both) e="both"; a="";;
      pixelnone1) e="pixelnone1"; a="";;
      ramp) e=""; a="--gi-adaptive-cap off"; export SOLARI_EXP_RAMP=0.1;;
      path) e=""; a="";;
      gate) e=""; a="";;
    esac
    g=restir; [ $v = path ] && g=path
    [ $v = gate ] && export SOLARI_EXP_GATE=0.1 || unset SOLARI_EXP_GATE
    out=/tmp/capx/${v}_${f}_${m}.exr
    SOLARI_EXP_CAP=$e $B render $SC --mode realtime --gi $g $a --frames $f --mean-of $m --size $SIZE --denoiser fallback --out $out >/dev/null 2>&1 || echo FAIL
    r=$($B compare $out $REF --json | python3 -c 'import json,sys; d=json.load(sys.stdin)["all"]; print("%.4f/%.3f"%(d["rel_mse"],d["mean_ratio"]))')
    echo "$v f$f m$m $r"
  done
done
