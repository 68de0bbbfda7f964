# Thirty-sixth session, lavapipe: relMSE of one binary along the orbit camera at 320x180
# (half scale unless SCALE is set) on four scenes and several frames, each against a 256-spp
# reference in /tmp/orb3 (made as motion2_2026-11-27/probe.sh says). Prints one line:
# NAME i8 i32 i96 m8 m32 m96 s8 s32 s96 c32 c96 (interior, many_lights, sun_boxes, Cornell box).
# usage: bash batch2.sh NAME BIN
n=$1; b=$2; shift 2
P=benches/results/motion2_2026-11-27/probe.sh
line="$n"
for sc in "interior 8" "interior 32" "interior 96" "many_lights 8" "many_lights 32" "many_lights 96" "sun_boxes 8" "sun_boxes 32" "sun_boxes 96" "cornell_box 32" "cornell_box 96"; do
  set -- $sc; s=$1; F=$2
  r=$(DIR=/tmp/orb3 FRAMES=$F bash $P $n $b $s --internal-scale ${SCALE:-0.5} | awk '{print $NF}')
  line="$line $r"
done
echo "$line"
