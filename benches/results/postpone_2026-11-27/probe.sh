#!/usr/bin/env bash
# Automatic quality's predictions against the measured frame, on the device: per scene and
# binary (BINS), `--quality auto` twice (its probe; JSON `quality.predicted_ms_per_setting`),
# then the defaults (`100-path`, the high tier) for 300 frames, all with --denoiser fallback
# at 1920x1080. The first auto run of a binary on a fresh machine finds the driver's shader
# cache cold (it is kept per executable), the second warm.
# Usage: BINS="..." bash benches/results/postpone_2026-11-27/probe.sh
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT/probe"
echo "scene,binary,run,predicted_100_path_ms,predicted_aa_path_ms,probe_s,measured_100_path_ms" > "$OUT/probe.csv"
for s in ${SCENES:-cornell_box interior}; do
  f=$(scene_file "$s")
  for b in $BINS; do
    for run in 1 2; do
      RUST_LOG=solari_renderer=debug /root/bins/$b render "$f" --mode realtime --quality auto \
        --denoiser fallback --size 1920x1080 --frames 3 --json --out "$OUT/probe/x.exr" \
        > "$OUT/probe/${s}_${b}_auto$run.json" 2> "$OUT/probe/${s}_${b}_auto$run.log"
    done
    /root/bins/$b render "$f" --mode realtime --denoiser fallback --size 1920x1080 \
      --frames 300 --json --out "$OUT/probe/x.exr" > "$OUT/probe/${s}_${b}_default.json" 2> /dev/null
    for run in 1 2; do
      python3 - "$OUT/probe/${s}_${b}_auto$run.json" "$OUT/probe/${s}_${b}_default.json" "$s" "$b" "$run" >> "$OUT/probe.csv" <<'PY'
import json, sys
a = json.load(open(sys.argv[1]))
d = json.load(open(sys.argv[2]))
q = a["quality"]
p = q["predicted_ms_per_setting"]
print(",".join(sys.argv[3:6] + [f'{p["100-path"]:.4f}', f'{p["aa-path"]:.4f}', f'{q["probe_s"]:.2f}',
                f'{d["gpu_frame_ms"]:.4f}']))
PY
    done
  done
  rm -f "$OUT/probe/x.exr"
done
tar czf "$OUT/probe.tar.gz" -C "$OUT" probe && rm -rf "$OUT/probe"
cat "$OUT/probe.csv"
