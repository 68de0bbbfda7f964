"""Tables of this folder's calls (README): `python3 table.py > table.md`. relMSE x1e3 without
the reference's noise, and each image's mean over its reference's."""
import os, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
from ab_runs import error_rows  # noqa: E402


def err(r):
    return "%.3f" % (1e3 * float(r["rel_mse_excess"]))


def means(r, q):
    return "%.4f, %.4f" % (float(r["mean_ratio"]), float(q["mean_ratio"]))


def variants(folder, scenes, names, ratio_head):
    """One row per scene and binary: raw and lit, frame 136 and the mean of frames 121-136."""
    ind = error_rows(os.path.join(here, folder, "indirect.csv"))
    lit = error_rows(os.path.join(here, folder, "lit.csv"))
    print(f"| scene | GI at the hit | raw f136 | raw mean of 16 | raw {ratio_head} "
          f"| lit f136 | lit mean of 16 | lit {ratio_head} |")
    print("|---|---|---|---|---|---|---|---|")
    for s in scenes:
        for b, name in names.items():
            a1, a16, l1, l16 = ind[(s, b, "1")], ind[(s, b, "16")], lit[(s, b, "1")], lit[(s, b, "16")]
            print(f"| {s} | {name} | {err(a1)} | {err(a16)} | {means(a1, a16)} "
                  f"| {err(l1)} | {err(l16)} | {means(l1, l16)} |")


variants("h100", ("interior", "sun_boxes", "metal_rough_spheres"),
         {"po": "path GI, base colour", "pn": "path GI, directional albedo",
          "ro": "ReSTIR GI, base colour", "rn": "ReSTIR GI, directional albedo"},
         "mean/ref (f136, mean of 16)")

print()
print("| scene | run | raw frame 32 | 136 | 500 | 2000 | lit frame 136 | 500 | 2000 |")
print("|---|---|---|---|---|---|---|---|---|")
fi = error_rows(os.path.join(here, "h100_frames", "indirect.csv"), by="frames")
fl = error_rows(os.path.join(here, "h100_frames", "lit.csv"), by="frames")
for s in ("interior", "cornell_box", "sun_boxes"):
    for b, n in (("p", "defaults"), ("pw64", "warm-up rounds for 64 frames")):
        raw = [fi.get((s, b, f)) for f in ("32", "136", "500", "2000")]
        lt = [fl.get((s, b, f)) for f in ("136", "500", "2000")]
        c = lambda r: "-" if r is None else "%s (%.4f)" % (err(r), float(r["mean_ratio"]))
        print(f"| {s} | {n} | " + " | ".join(c(r) for r in raw) + " | " + " | ".join(c(r) for r in lt) + " |")

print()
variants("h100_average", ("interior", "metal_rough_spheres"),
         {"po": "base colour", "pn": "directional albedo (kept)", "pa": "albedo averaged over views"},
         "mean/ref")
