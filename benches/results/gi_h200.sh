#!/usr/bin/env bash
# GI modes on the H200 (device tool), one command. Issue 18, "Time against error" (first
# slice: diffuse GI, and specular GI with a mode ending in +spec; no PSR yet):
#   1. timing at 1920x1080: `solari render --mode realtime --gi MODE --denoiser fallback
#      --frames 200 --json` per scene and mode (per-pass GPU ms in the summary);
#   2. error at 960x540 (a quarter of the pixels, so `solari compare` stays quick): the
#      last frame and the mean of 16 frames (`--mean-of 16`) after 120, against a full-bounce
#      reference (`--mode reference --spp $SPP`, default bounces).
# Needs .gl, .dev/solari (stripped release build of the commit under test) and .dev/scenes
# carried. Usage: bash benches/results/gi_h200.sh   (SCENES, MODES, SPP, PHASES override). A
# mode is a GI mode with optional suffixes: +spec adds `--specular-gi`, +nodi runs ReSTIR DI
# without reuse (`--di-reuse none`), e.g. MODES="path path+spec path+spec+nodi". PHASES="time
# error" (default both) runs either half alone, so a long sweep can span two device commands.
# Everything lands in $OUT/gi_h200.tar.gz.
set -u
source benches/results/device_env.sh
BIN=${SOLARI_BIN:-.dev/solari}
R=${RESULTS:-/root/gi}
SPP=${SPP:-1024}
SCENES=${SCENES:-cornell_box sun_boxes many_lights interior}
MODES=${MODES:-off cache path restir}
mkdir -p "$R" "$OUT"
PHASES=${PHASES:-time error}
# "cache+spec+nodi" -> --gi cache --specular-gi --di-reuse none
flags() {
  local parts; IFS=+ read -ra parts <<< "$1"
  echo "--gi ${parts[0]}"
  for p in "${parts[@]:1}"; do
    case $p in spec) echo "--specular-gi" ;; nodi) echo "--di-reuse none" ;;
      *) echo "unknown mode suffix +$p" >&2; exit 2 ;; esac
  done
}
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
for s in $SCENES; do
  [[ " $PHASES " == *" time "* ]] || break
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  for g in $MODES; do
    echo "== $s $g timing $(date -u +%T)" >&2
    "$BIN" render "$f" --mode realtime $(flags "$g") --denoiser fallback --frames 200 \
      --size 1920x1080 --json --out "$R/x.png" > "$R/${s}_${g}_1080p.json" 2> "$R/${s}_${g}_1080p.log"
  done
done
for s in $SCENES; do
  [[ " $PHASES " == *" error "* ]] || break
  f=$(ls .dev/scenes/"$s"/*.gltf | head -n 1)
  echo "== $s reference $(date -u +%T)" >&2
  "$BIN" render "$f" --mode reference --spp "$SPP" --size 960x540 --out "$R/${s}_ref.exr" \
    --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  for g in $MODES; do
    for m in 1 16; do
      n="${s}_${g}_mean$m"
      "$BIN" render "$f" --mode realtime $(flags "$g") --denoiser fallback --frames 136 \
        --mean-of $m --size 960x540 --json --out "$R/$n.exr" > "$R/$n.json" 2> "$R/$n.log"
      "$BIN" compare "$R/$n.exr" "$R/${s}_ref.exr" --json > "$R/$n.compare.json" 2>> "$R/$n.log"
      rm -f "$R/$n.exr"
    done
  done
  rm -f "$R/${s}_ref.exr"
done
tar czf "$OUT/gi_h200.tar.gz" -C "$R" --exclude='*.exr' --exclude='x.png' .
python3 - "$R" "$MODES" <<'PY' || true
import json, os, sys
r = sys.argv[1]
def load(p):
    try:
        return json.load(open(os.path.join(r, p)))
    except Exception:
        return None
scenes = sorted({f.split("_ref.json")[0] for f in os.listdir(r) if f.endswith("_ref.json")})
for s in scenes:
    for g in sys.argv[2].split():
        t = load(f"{s}_{g}_1080p.json") or {}
        p = t.get("passes", {})
        if not t:
            continue
        gi = sum((p.get(n) or {}).get("mean_ms") or 0 for n in ("gi_initial_temporal", "gi_spatial_shade", "world_cache_gi"))
        spec = (p.get("specular_gi") or {}).get("mean_ms") or 0
        e = [(load(f"{s}_{g}_mean{m}.compare.json") or {}).get("all", {}) for m in (1, 16)]
        print(f"{s:14} {g:16} GPU {t.get('gpu_frame_ms') or float('nan'):7.3f} ms  GI passes {gi:6.3f} ms  specular {spec:6.3f} ms  "
              f"relMSE 1 frame {e[0].get('rel_mse', float('nan')):.5f}  16 frames {e[1].get('rel_mse', float('nan')):.5f}  "
              f"FLIP {e[0].get('flip', float('nan')):.4f}  mean/ref {e[0].get('mean_ratio') or float('nan'):.4f}")
PY
