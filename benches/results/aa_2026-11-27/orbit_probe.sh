#!/usr/bin/env bash
# Thirty-second session, lavapipe: error at frame FRAMES (default 32) of the orbit camera at
# 160x90 against one full-bounce reference per scene, for one variant of the real-time
# renderer. References first (256 spp, once):
#   for s in cornell_box many_lights interior sun_boxes; do
#     target/release/solari render crates/solari-testdata/scenes/$s/$s.gltf --mode reference \
#       --camera-path orbit --frames 32 --spp 256 --size 160x90 --out $DIR/ref_$s.exr; done
# Usage: DIR=/tmp/orb bash orbit_probe.sh NAME "ENV=VALUE ..." [realtime flags]
#   (DEN picks the denoiser, default fallback; SCENES the scenes; the experiment variables
#   SOLARI_EXP_UP_* need experiments/upscaler_motion_env.patch applied.)
# Prints relMSE, RMSE, FLIP and mean over the reference per scene.
set -u
name=$1; envs=$2; shift 2
B=${SOLARI_BIN:-target/release/solari}; T=crates/solari-testdata/scenes; D=${DIR:-/tmp/orb}
for s in ${SCENES:-cornell_box many_lights sun_boxes interior}; do
  [ -f "$D/ref_$s.exr" ] || continue
  f=$(ls $T/$s/*.gltf | head -1)
  env $envs "$B" render "$f" --mode realtime --camera-path orbit --denoiser "${DEN:-fallback}" \
    --frames "${FRAMES:-32}" --size 160x90 "$@" --out "$D/x_${name}_$s.exr" > /dev/null 2>&1
  "$B" compare "$D/x_${name}_$s.exr" "$D/ref_$s.exr" --json | python3 -c "import json,sys; a=json.load(sys.stdin)['all']; print('$name $s relMSE %.5f rmse %.4f flip %.4f mean %.4f'%(a['rel_mse'],a['rmse'],a['flip'],a['mean_ratio']))"
done
