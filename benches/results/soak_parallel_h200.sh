#!/usr/bin/env bash
# Long soak runs on the H200 (device tool) that outlast one device command: `start` launches
# the runs in a new process session (the device tool lets such a process run on between calls
# until the machine goes back) and returns; each later `poll [SECONDS]` call waits up to
# SECONDS (default 570) for them, then copies the summaries and logs so far into $OUT.
#
# A run of 100,000 frames of `interior` at 1080p takes about 16 minutes alone, longer than one
# device command may run (10 minutes), shorter than a machine is held (30 minutes). Several
# runs share the GPU at once: frame times of such runs measure the sharing, not the renderer;
# what they prove is the absence of non-finite values, overflows and memory growth.
#
# Needs, carried in the working tree: .gl/ (Vulkan loader packages, see the device README)
# and .dev/bins.tar.xz (its `solari`: a stripped release build of the commit under test, as
# benches/results/device_env.sh unpacks it); the scenes are the repository's
# (crates/solari-testdata/scenes). Usage (device commands):
#   SEQUENTIAL=1 RUNS="interior:1000 sun_boxes:" bash benches/results/soak_parallel_h200.sh start
#   bash benches/results/soak_parallel_h200.sh poll 570
# RUNS lists scene:toggle pairs (empty toggle: static lights); FRAMES defaults to 100000;
# SEQUENTIAL=1 runs them one after another. ADAPTER=N runs them on the Nth GPU
# (SOLARI_ADAPTER); on a machine with several GPUs, call `start` once per GPU in one command,
# each with its own ADAPTER and RUNS. Never pipe `start` (e.g. into `tail`): the runs
# inherit its stdout, so the pipe stays open, the device command runs into its time limit and
# looks failed, and a second `start` would run a second chain beside the first. The machine goes back 30 s after a command ends
# with no next one, killing the runs: issue the polls back to back.
# Settings as in soak_h200_2026-11-23.sh: 1920x1080, orbit camera, cache GI, fallback
# denoiser, software BVH, the non-finite detector on every pass of every frame. GI_ARGS
# replaces the GI and denoiser options (default "--gi cache --denoiser fallback"), e.g.
# GI_ARGS="--gi path --specular-gi on --denoiser fallback" for the GI soak of issue 18.
set -u
DIR=/root/soak
case "${1:-}" in
start)
  source benches/results/device_env.sh
  mkdir -p "$DIR"
  # The working tree may be replaced by the next call: run from a private copy.
  # A second `start` (another GPU) must not overwrite the binary or script the first runs.
  if [ ! -e "$DIR/solari" ]; then
    unpack_bins
    cp /root/bins/solari "$DIR/"
    cp -r crates/solari-testdata/scenes "$DIR/"
  fi
  FRAMES=${FRAMES:-100000}
  # One chain of runs, one after another (SEQUENTIAL=1), or all at once (the default). Two
  # runs sharing the H200 reached only about 78% of its throughput (context switching).
  [ -e "$DIR/run_one.sh" ] || cat > "$DIR/run_one.sh" <<'ONE'
s=${1%%:*}; t=${1#*:}; name="$s-${t:-static}"
[ -n "${ADAPTER:-}" ] && export SOLARI_ADAPTER=$ADAPTER
file=$(ls "$DIR/scenes/$s"/*.gltf | head -n 1)
toggle=(); [ -n "$t" ] && toggle=(--toggle-lights "$t")
echo "== $s frames=$FRAMES toggle=${t:-none} adapter=${ADAPTER:-best} start $(date -u +%T)" > "$DIR/$name.log"
"$DIR/solari" soak "$file" --frames "$FRAMES" --size 1920x1080 --camera-path orbit \
  $GI_ARGS "${toggle[@]}" --progress-every 10000 \
  --summary "$DIR/$name.json" < /dev/null 2>> "$DIR/$name.log" > /dev/null
echo "exit $? $(date -u +%T)" >> "$DIR/$name.log"
ONE
  export DIR FRAMES=${FRAMES:-100000} ADAPTER=${ADAPTER:-}
  export GI_ARGS=${GI_ARGS:-"--gi cache --denoiser fallback"}
  if [ "${SEQUENTIAL:-0}" = 1 ]; then
    # Logs of runs still queued exist from the start, so `poll` waits for them too.
    for run in ${RUNS:?RUNS=scene:toggle ...}; do
      t=${run#*:}; echo "== ${run%%:*} queued" > "$DIR/${run%%:*}-${t:-static}.log"
    done
    setsid bash -c 'for r in "$@"; do bash "$DIR/run_one.sh" "$r"; done' _ $RUNS < /dev/null &
  else
    for run in ${RUNS:?RUNS=scene:toggle ...}; do
      setsid bash "$DIR/run_one.sh" "$run" < /dev/null &
    done
  fi
  sleep 20
  nvidia-smi --query-gpu=index,name,driver_version,utilization.gpu,memory.used --format=csv
  tail -n 3 "$DIR"/*.log
  ;;
poll)
  end=$((SECONDS + ${2:-570}))
  while [ $SECONDS -lt $end ] && [ "$(grep -l '^exit ' "$DIR"/*.log | wc -l)" -lt "$(ls "$DIR"/*.log | wc -l)" ]; do
    sleep 10
  done
  mkdir -p "$OUT"
  cp "$DIR"/*.log "$OUT"/ 2>/dev/null
  cp "$DIR"/*.json "$OUT"/ 2>/dev/null
  nvidia-smi --query-gpu=index,utilization.gpu,memory.used --format=csv
  tail -n 2 "$DIR"/*.log
  ;;
*)
  echo "usage: soak_parallel_h200.sh start|poll [SECONDS]" >&2
  exit 2
  ;;
esac
