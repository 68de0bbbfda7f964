#!/usr/bin/env bash
# On a workstation (lavapipe): DI in one pass against two. Renders each scene with reuse off,
# GI and specular GI off and no denoiser (deterministic on lavapipe) with OLD (a build before
# the one-pass change, ed5883d in the session) and NEW, and compares the images.
# Usage: OLD=path/to/solari NEW=target/release/solari bash benches/results/di_reuse_2026-11-26/one_pass_exact.sh
set -u
OLD=${OLD:?a solari binary built before the change}
NEW=${NEW:-target/release/solari}
T=$(mktemp -d)
for s in cornell_box interior many_lights sun_boxes; do
  f=$(ls crates/solari-testdata/scenes/$s/*.gltf | head -1)
  for b in old:$OLD new:$NEW; do
    "${b#*:}" render "$f" --mode realtime --frames 6 --size 96x64 --gi off --specular-gi off \
      --denoiser none --di-reuse none --out "$T/${s}_${b%%:*}.exr" > /dev/null 2>&1
  done
  if cmp -s "$T/${s}_old.exr" "$T/${s}_new.exr"; then
    echo "$s identical"
  else
    echo "$s differs: $("$NEW" compare "$T/${s}_new.exr" "$T/${s}_old.exr" | tail -1)"
  fi
done
rm -rf "$T"
