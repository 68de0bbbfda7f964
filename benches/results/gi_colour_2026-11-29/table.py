"""The tables of benches/RESULTS.md's "Colour noise" section from h200_1/: GI alone, raw,
relMSE x 10^3 without the reference's noise (indirect.csv), the GI passes' GPU ms at
1920x1080 (time.tar.gz: medians of two reps of the per-pass means; path GI's one-candidate
time and the rbo time are the forty-fifth session's and this call's rb's), the product of
the two (relMSE x ms: lower is more efficient) and the factor at equal time against one-
candidate path GI (its relMSE x ms over the row's). Usage: python3 table.py"""
import csv, io, json, os, statistics, tarfile

here = os.path.dirname(os.path.abspath(__file__))
rows = list(csv.DictReader(open(os.path.join(here, "h200_1/indirect.csv"))))
times = {}
with tarfile.open(os.path.join(here, "h200_1/time.tar.gz")) as t:
    for m in t.getmembers():
        n = os.path.basename(m.name)
        if not (n.startswith("ab_") and n.endswith(".json")):
            continue
        scene, b, _ = n[3:-5].rsplit("_", 2)
        j = json.load(t.extractfile(m))
        gi = sum(v["mean_ms"] for k, v in j["passes"].items() if k.startswith("gi_") and v["mean_ms"])
        times.setdefault((scene, b), []).append(gi)
ms = {k: statistics.median(v) for k, v in times.items()}
# One-candidate path GI's GI pass (not in this call's timing): the forty-fifth session's
# (gi_indirect_2026-11-29/table.md, the same pass).
ms[("cornell_box", "p")] = 0.217
ms[("interior", "p")] = 0.826
for s in ("cornell_box", "interior"):
    ms[(s, "rbo")] = ms[(s, "rb")]  # the same rays; only the shading differs
err = {(r["scene"], r["binary"], r["mean_of"]): 1e3 * float(r["rel_mse_excess"]) for r in rows}
names = {"p": "path GI", "p2": "path GI, 2 candidates", "p4": "path GI, 4 candidates",
         "r": "ReSTIR GI (chosen ray)", "rb": "ReSTIR GI, two rays, both shaded",
         "rbo": "ReSTIR GI, two rays, chosen shaded"}
print("| scene | mode | GI ms | raw f136 | raw mean of 16 | f136 × ms | equal-time factor vs path GI |")
print("|---|---|---|---|---|---|---|")
for s in ("cornell_box", "interior"):
    base = err[(s, "p", "1")] * ms[(s, "p")]
    for b in ("p", "p2", "p4", "r", "rb", "rbo"):
        e1, e16, t = err[(s, b, "1")], err[(s, b, "16")], ms[(s, b)]
        print(f"| {s} | {names[b]} | {t:.3f} | {e1:.2f} | {e16:.3f} | {e1 * t:.2f} | {base / (e1 * t):.2f} |")
