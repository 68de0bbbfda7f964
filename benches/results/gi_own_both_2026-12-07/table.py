"""The own-share experiment's table (README): GI ms (median over the reps of the GI passes'
mean GPU ms at 1920x1080, `h100_1/time.tar.gz`), the indirect view's raw relMSE x10^3
without the reference's noise at 960x540 (`h100_1/indirect.csv`: frame 136 and the mean of
frames 121-136), one frame's mean over the reference's, relMSE x ms, and one-candidate path
GI's product over the row's (the equal-time factor of issue 18's bar). Writes table.md."""
import os, sys
from statistics import median

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
from ab_runs import error_rows, gi_ms, runs_in_tarball  # noqa: E402

NAMES = {"p": "path GI", "r": "ReSTIR GI, own share over both samples (the patch's default)",
         "ro": "ReSTIR GI, own share from the kept sample (shipped)"}
runs = runs_in_tarball(os.path.join(here, "h100_1", "time.tar.gz"))
err = {k: (float(r["rel_mse_excess"]), float(r["mean_ratio"]))
       for k, r in error_rows(os.path.join(here, "h100_1", "indirect.csv")).items()}
lines = ["| scene | mode | GI ms | raw f136 | raw mean of 16 | f136 mean/ref | f136 x ms | factor vs path GI |",
         "|---|---|---|---|---|---|---|---|"]
for s in ("cornell_box", "interior"):
    base = None
    for b in ("p", "r", "ro"):
        ms = median(gi_ms(x) for x in runs[(s, b)])
        e1, ratio = err[(s, b, "1")]
        e16 = err[(s, b, "16")][0]
        prod = e1 * 1e3 * ms
        base = base or prod
        lines.append(f"| {s} | {NAMES[b]} | {ms:.4f} | {e1 * 1e3:.2f} | {e16 * 1e3:.3f} | {ratio:.4f} "
                     f"| {prod:.2f} | {base / prod:.2f} |")
open(os.path.join(here, "table.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
