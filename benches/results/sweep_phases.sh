# Sourced by the device sweeps (quality_h200.sh, cache_refine_h200.sh): the time and error
# phases over SCENES × SETTINGS, the same for every sweep. The caller sets BIN (the solari
# binary), R (the results folder), SCENES, SETTINGS, SPP, and defines `flags SETTING` (the
# render options of one setting). Files per scene s and setting g, in $R:
#   time:  ${s}_${g}_time.json/.log: 1920x1080, 200 frames, fallback denoiser, --json;
#   error: ${s}_ref.json/.log (the --spp $SPP full-bounce reference at $ERROR_SIZE, default
#          960x540) and ${s}_${g}_error.json/.log/.compare.json: frame 136 of a still camera
#          against it;
#   orbit: ${s}_ref_orbit${n}.json/.log (a reference of frame n of the orbit camera, n in
#          ORBIT_FRAMES, default "32 96") and ${s}_${g}_orbit${n}.json/.log/.compare.json:
#          frame n of the orbit (a moving camera) against it, at $ERROR_SIZE.
# Every reference is rendered with its per-pixel variance (`--variance-out`) and every
# compare takes it (`--reference-variance`), so each .compare.json also holds the
# reference's own noise (`reference_noise`; benches/RESULTS.md, "The reference's own noise").

# scene_file comes from device_env.sh, which every device script sources first.

# Records the card and the binary's commit beside the results.
sweep_describe() {
  nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
  cp .dev/SOLARI_COMMIT "$R/" 2>/dev/null
}

sweep_time() {
  # Warm-up: the first runs of a phase read 1.8-2x slow on the H100 (clocks ramping?).
  $BIN render "$(scene_file cornell_box)" --mode realtime --frames 600 --size 1920x1080 \
    --out "$R/x.png" > /dev/null 2>&1
  local s f g
  for s in $SCENES; do
    f=$(scene_file "$s")
    for g in $SETTINGS; do
      echo "== $s $g time $(date -u +%T)" >&2
      $BIN render "$f" --mode realtime $(flags "$g") --denoiser fallback --frames 200 \
        --size 1920x1080 --json --out "$R/x.png" > "$R/${s}_${g}_time.json" 2> "$R/${s}_${g}_time.log"
    done
  done
  rm -f "$R/x.png"
}

sweep_error() {
  local s f g n size=${ERROR_SIZE:-960x540}
  for s in $SCENES; do
    f=$(scene_file "$s")
    echo "== $s reference $(date -u +%T)" >&2
    $BIN render "$f" --mode reference --spp "$SPP" --size "$size" --out "$R/${s}_ref.exr" \
      --variance-out "$R/${s}_var.exr" --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
    for g in $SETTINGS; do
      n="${s}_${g}_error"
      $BIN render "$f" --mode realtime $(flags "$g") --denoiser fallback --frames 136 \
        --size "$size" --json --out "$R/$n.exr" > "$R/$n.json" 2> "$R/$n.log"
      $BIN compare "$R/$n.exr" "$R/${s}_ref.exr" --reference-variance "$R/${s}_var.exr" --json \
        > "$R/$n.compare.json" 2>> "$R/$n.log"
      rm -f "$R/$n.exr"
    done
    rm -f "$R/${s}_ref.exr" "$R/${s}_var.exr"
  done
}

sweep_orbit() {
  local s f g n m size=${ERROR_SIZE:-960x540}
  for s in $SCENES; do
    f=$(scene_file "$s")
    for n in ${ORBIT_FRAMES:-32 96}; do
      echo "== $s orbit reference $n $(date -u +%T)" >&2
      $BIN render "$f" --mode reference --camera-path orbit --frames "$n" --spp "$SPP" \
        --size "$size" --out "$R/${s}_ref_orbit$n.exr" --variance-out "$R/${s}_var_orbit$n.exr" \
        --json > "$R/${s}_ref_orbit$n.json" 2> "$R/${s}_ref_orbit$n.log"
      for g in $SETTINGS; do
        m="${s}_${g}_orbit$n"
        $BIN render "$f" --mode realtime $(flags "$g") --denoiser fallback --camera-path orbit \
          --frames "$n" --size "$size" --json --out "$R/$m.exr" > "$R/$m.json" 2> "$R/$m.log"
        $BIN compare "$R/$m.exr" "$R/${s}_ref_orbit$n.exr" \
          --reference-variance "$R/${s}_var_orbit$n.exr" --json > "$R/$m.compare.json" 2>> "$R/$m.log"
        rm -f "$R/$m.exr"
      done
      rm -f "$R/${s}_ref_orbit$n.exr" "$R/${s}_var_orbit$n.exr"
    done
  done
}
