"""Temporal-only ReSTIR GI (`--gi-reuse temporal`) beside path GI and full ReSTIR GI (README):
GI ms (median over the reps of the GI passes' mean GPU ms at 1920x1080, h100_1/time.tar.gz),
GI alone raw (h100_1/indirect.csv) and the lit frame through the fallback denoiser
(h100_2/lit.csv), relMSE x10^3 without the reference's noise at 960x540, frame 136 and the
mean of frames 121-136, and each reading's equal-time factor against path GI: path GI's
relMSE x ms over the row's. The orbit camera's frames 32 and 96 (h100_2/orbit.csv, relMSE
x10^3 against a reference of that frame). Writes table.md."""
import csv, os, sys
from statistics import median

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
from ab_runs import error_rows, gi_ms, runs_in_tarball  # noqa: E402

NAMES = {"p": "path GI", "r": "ReSTIR GI (defaults)", "rt": "temporal only",
         "rt16": "temporal only, cap 16", "rt32": "temporal only, cap 32"}
runs = runs_in_tarball(os.path.join(here, "h100_1", "time.tar.gz"))


def errors(path):
    return {k: float(r["rel_mse_excess"]) * 1e3 for k, r in error_rows(os.path.join(here, path)).items()}


raw, lit = errors("h100_1/indirect.csv"), errors("h100_2/lit.csv")
orbit = {(r["scene"], r["binary"], r["frame"]): float(r["rel_mse"]) * 1e3
         for r in csv.DictReader(open(os.path.join(here, "h100_2", "orbit.csv")))}
out = ["| scene | mode | GI ms | raw f136 | raw mean of 16 | factor, raw f136 | factor, raw mean of 16 "
       "| lit f136 | lit mean of 16 | factor, lit f136 | orbit f32 | orbit f96 |",
       "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for s in ("cornell_box", "interior"):
    ms = {b: median(gi_ms(x) for x in runs[(s, b)]) for b in NAMES}
    for b, name in NAMES.items():
        f = lambda e: e[(s, "p", "1")] * ms["p"] / (e[(s, b, "1")] * ms[b])
        f16 = raw[(s, "p", "16")] * ms["p"] / (raw[(s, b, "16")] * ms[b])
        row = [s, name, f"{ms[b]:.4f}", f"{raw[(s, b, '1')]:.2f}", f"{raw[(s, b, '16')]:.3f}",
               f"{f(raw):.2f}", f"{f16:.2f}"]
        if (s, b, "1") in lit:
            row += [f"{lit[(s, b, '1')]:.4f}", f"{lit[(s, b, '16')]:.4f}", f"{f(lit):.2f}",
                    f"{orbit[(s, b, '32')]:.3f}", f"{orbit[(s, b, '96')]:.3f}"]
        else:
            row += [""] * 5
        out.append("| " + " | ".join(row) + " |")
open(os.path.join(here, "table.md"), "w").write("\n".join(out) + "\n")
print("\n".join(out))
