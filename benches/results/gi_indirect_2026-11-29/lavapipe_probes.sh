#!/usr/bin/env bash
# The lavapipe probes behind "GI's own error" (benches/RESULTS.md), on this workstation's CPU
# Vulkan (llvmpipe, LLVM 15; 2 cores), with `cargo build --release -p solari-app` of the
# commit named per probe. The Cornell box at 128x128, the indirect view against a
# `--min-bounces 2` reference of 2048 paths at pixel centres with its variance; each line
# prints the mean ratio against the reference and relMSE without the reference's noise.
#   cap:   `converged` = mean of frames 137-200, raw (`--frames 200 --mean-of 64`), and raw
#          frames 8 and 24; ReSTIR GI as built (3415810: the cap always on, +4.0% to +5.2%),
#          with `--gi-adaptive-cap off` (+0.2% to +0.7%), `--gi-spatial-visibility both`
#          (+1.1%), `--gi-spatial-radius 2` (+1.5%); at 4d1c202 the default (the cap stops:
#          +0.7%) and `--gi-adaptive-cap-settle never` (+4.9%). The dead-zone variant (+7.2%)
#          was a temporary edit of `restir_gi_initial.wesl` (the cap at its maximum below 5%
#          relative change), not kept.
#   floor: raw frame 136 of path GI with 1, 4 and 16 candidates and of ReSTIR GI (0.135,
#          0.0449, 0.0229, 0.036 at 867721f's parent); the same with `--specular-gi off`
#          (unchanged). Two temporary edits, not kept, gave the same figures: the world cache's
#          `max_temporal_samples` 30 -> 120 (settings.rs), and its blend without the adaptive
#          cap (world_cache_blend.wesl); ReSTIR GI's `confidence_cap` 8 -> 24 raised its error
#          0.035 -> 0.044.
# Usage: bash benches/results/gi_indirect_2026-11-29/lavapipe_probes.sh cap|floor [EXTRA FLAGS]
set -u
S=${SOLARI:-target/release/solari}
C=crates/solari-testdata/scenes/cornell_box/cornell_box.gltf
W=${WORK:-/tmp/gi_indirect_probes}; mkdir -p "$W"
[ -f "$W/ref.exr" ] || $S render $C --mode reference --min-bounces 2 --spp 2048 --pixel-centre \
  --size 128x128 --out "$W/ref.exr" --variance-out "$W/var.exr" > /dev/null
measure() { # image tag
  $S compare "$1" "$W/ref.exr" --reference-variance "$W/var.exr" --json | python3 -c \
    'import json,sys; d=json.load(sys.stdin); print(sys.argv[1], "%.4f %.5f" % (d["all"]["mean_ratio"], d["reference_noise"]["all"]["rel_mse_excess"]))' "$2"
}
rt() { $S render $C --mode realtime --view indirect --denoiser none --size 128x128 "$@" > /dev/null; }
phase=${1:-}; shift || true
case "$phase" in
  cap)
    rt --gi restir --frames 200 --mean-of 64 "$@" --out "$W/c.exr"; measure "$W/c.exr" converged
    for f in 8 24; do rt --gi restir --frames $f "$@" --out "$W/f$f.exr"; measure "$W/f$f.exr" frame$f; done ;;
  floor)
    for n in 1 4 16; do rt --gi path --gi-samples $n --frames 136 "$@" --out "$W/p$n.exr"; measure "$W/p$n.exr" path$n; done
    rt --gi restir --frames 136 "$@" --out "$W/r.exr"; measure "$W/r.exr" restir ;;
  *) echo "usage: $0 cap|floor [EXTRA FLAGS]" >&2; exit 2 ;;
esac
