"""The tables of benches/RESULTS.md's "Colour noise" section from h200_1/: GI alone, raw,
relMSE x 10^3 without the reference's noise (indirect.csv), the GI passes' GPU ms at
1920x1080 (time.tar.gz: medians of two reps of the per-pass means; path GI's one-candidate
time and the rbo time are the forty-fifth session's and this call's rb's), the product of
the two (relMSE x ms: lower is more efficient) and the factor at equal time against one-
candidate path GI (its relMSE x ms over the row's). Usage: python3 table.py"""
import csv, os, statistics, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
import ab_runs  # noqa: E402 (benches/results/ab_runs.py)


def gi_ms(folder):
    """Median over reps of each (scene, binary)'s GI passes' summed mean GPU ms."""
    runs = ab_runs.runs_in_tarball(os.path.join(here, folder, "time.tar.gz"))
    return {k: statistics.median(ab_runs.gi_ms(j) for j in v) for k, v in runs.items()}


rows = list(csv.DictReader(open(os.path.join(here, "h200_1/indirect.csv"))))
ms = gi_ms("h200_1")
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

# Call 2 (h200_2/): the pixel's own reservoir's share (`--gi-own-share 0` / `0.5`), with the
# one-ray merge (r0, r5) and with two rays and both samples shaded (rb0, rb5; since this call
# the share is ignored there). GI ms: interior from this call's timing (r0 and r5 run the same
# passes, the share being a uniform); the Cornell box's were not timed in this call.
rows2 = list(csv.DictReader(open(os.path.join(here, "h200_2/indirect.csv"))))
ms2 = gi_ms("h200_2")
err2 = {(r["scene"], r["binary"], r["mean_of"]): 1e3 * float(r["rel_mse_excess"]) for r in rows2}
names2 = {"r0": "ReSTIR GI, one ray, own share 0", "r5": "ReSTIR GI, one ray, own share 0.5",
          "rb0": "ReSTIR GI, two rays, both shaded, share 0", "rb5": "two rays, both shaded, share 0.5 (blended)"}
print()
print("| scene | mode | GI ms | raw f136 | raw mean of 16 | f136 × ms | equal-time factor vs path GI |")
print("|---|---|---|---|---|---|---|")
for s in ("cornell_box", "interior"):
    base = err[(s, "p", "1")] * ms[(s, "p")]
    for b in ("r0", "r5", "rb0", "rb5"):
        e1, e16 = err2[(s, b, "1")], err2[(s, b, "16")]
        t = ms2.get((s, b))
        if t is None:
            print(f"| {s} | {names2[b]} | (not timed) | {e1:.2f} | {e16:.3f} | | |")
        else:
            print(f"| {s} | {names2[b]} | {t:.3f} | {e1:.2f} | {e16:.3f} | {e1 * t:.2f} | {base / (e1 * t):.2f} |")
