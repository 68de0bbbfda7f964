"""Tables of this folder's calls (README): `python3 table.py`. relMSE x1e3 without the
reference's noise, and each image's mean over its reference's."""
import csv, os, sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from ab_runs import error_rows  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
names = {"po": "path GI, base colour", "pn": "path GI, directional albedo",
         "ro": "ReSTIR GI, base colour", "rn": "ReSTIR GI, directional albedo"}
ind = error_rows(os.path.join(here, "h100", "indirect.csv"))
lit = error_rows(os.path.join(here, "h100", "lit.csv"))
print("| scene | GI at the hit | raw f136 | raw mean of 16 | raw mean/ref (f136, mean of 16) "
      "| lit f136 | lit mean of 16 | lit mean/ref (f136, mean of 16) |")
print("|---|---|---|---|---|---|---|---|")
for s in ("interior", "sun_boxes", "metal_rough_spheres"):
    for b in ("po", "pn", "ro", "rn"):
        a1, a16, l1, l16 = ind[(s, b, "1")], ind[(s, b, "16")], lit[(s, b, "1")], lit[(s, b, "16")]
        e = lambda r: "%.3f" % (1e3 * float(r["rel_mse_excess"]))
        m = lambda r, q: "%.4f, %.4f" % (float(r["mean_ratio"]), float(q["mean_ratio"]))
        print(f"| {s} | {names[b]} | {e(a1)} | {e(a16)} | {m(a1, a16)} | {e(l1)} | {e(l16)} | {m(l1, l16)} |")

print()
print("| scene | run | raw frame 32 | 136 | 500 | 2000 | lit frame 136 | 500 | 2000 |")
print("|---|---|---|---|---|---|---|---|---|")
def by_frames(path):
    out = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            out[(r["scene"], r["binary"], r["frames"])] = r
    return out
fi, fl = by_frames(os.path.join(here, "h100_frames", "indirect.csv")), by_frames(os.path.join(here, "h100_frames", "lit.csv"))
for s in ("interior", "cornell_box", "sun_boxes"):
    for b, n in (("p", "defaults"), ("pw64", "warm-up rounds for 64 frames")):
        raw = [fi.get((s, b, f)) for f in ("32", "136", "500", "2000")]
        lt = [fl.get((s, b, f)) for f in ("136", "500", "2000")]
        c = lambda r: "-" if r is None else "%.3f (%.4f)" % (1e3 * float(r["rel_mse_excess"]), float(r["mean_ratio"]))
        print(f"| {s} | {n} | " + " | ".join(c(r) for r in raw) + " | " + " | ".join(c(r) for r in lt) + " |")

print()
av = error_rows(os.path.join(here, "h100_average", "indirect.csv"))
al = error_rows(os.path.join(here, "h100_average", "lit.csv"))
names3 = {"po": "base colour", "pn": "directional albedo (kept)", "pa": "albedo averaged over views"}
print("| scene | GI at the hit | raw f136 | raw mean of 16 | raw mean/ref | lit f136 | lit mean of 16 | lit mean/ref |")
print("|---|---|---|---|---|---|---|---|")
for s in ("interior", "metal_rough_spheres"):
    for b in ("po", "pn", "pa"):
        a1, a16, l1, l16 = av[(s, b, "1")], av[(s, b, "16")], al[(s, b, "1")], al[(s, b, "16")]
        e = lambda r: "%.3f" % (1e3 * float(r["rel_mse_excess"]))
        m = lambda r, q: "%.4f, %.4f" % (float(r["mean_ratio"]), float(q["mean_ratio"]))
        print(f"| {s} | {names3[b]} | {e(a1)} | {e(a16)} | {m(a1, a16)} | {e(l1)} | {e(l16)} | {m(l1, l16)} |")
