# Sourced by run.sh and lavapipe.sh: `row SCENE WHAT COMPARE_JSON` prints one CSV row of a
# `solari compare --json` result (relMSE, RMSE, FLIP, mean / reference, and the reference's
# own noise with the relMSE above it).
row() {
  python3 - "$3" "$1" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); a = d.get("all", d)
n = (d.get("reference_noise") or {}).get("all") or {}
print(",".join(sys.argv[2:4] + [str(a.get(k)) for k in ("rel_mse", "rmse", "flip", "mean_ratio")]
               + [str(n.get(k)) for k in ("rel_mse", "rel_mse_excess")]))
PY
}
