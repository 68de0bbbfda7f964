"""The table of benches/RESULTS.md's cache GI section (one device call, folder h100/ or the
first argument): GI alone, raw (`--view indirect --denoiser none`, frame 136 and the mean of
frames 121-136), relMSE x 10^3 without the reference's noise and the image's mean against the
reference's, beside each mode's GI passes' and specular GI's GPU ms at 1920x1080 (medians of
two reps) and the one-frame product relMSE x ms against one-candidate path GI's, by GI ms and
by GI + specular ms. Usage: python3 table.py [FOLDER]"""
import os, statistics, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
import ab_runs  # noqa: E402 (benches/results/ab_runs.py)

folder = os.path.join(here, sys.argv[1] if len(sys.argv) > 1 else "h100")
runs = ab_runs.runs_in_tarball(os.path.join(folder, "time.tar.gz"))


# GI: path and ReSTIR GI's passes (gi_*) or cache GI's lookup (world_cache_gi).
gi = {k: statistics.median(ab_runs.passes_ms(j, ("gi_", "world_cache_gi")) for j in v) for k, v in runs.items()}
spec = {k: statistics.median(ab_runs.passes_ms(j, ("specular_gi",)) for j in v) for k, v in runs.items()}
frame = {k: statistics.median(j["gpu_frame_ms"] for j in v) for k, v in runs.items()}
ind = {k: (1e3 * float(r["rel_mse_excess"]), float(r["mean_ratio"]))
       for k, r in ab_runs.error_rows(os.path.join(folder, "indirect.csv")).items()}
names = {"p": "path GI", "c": "cache GI", "r": "ReSTIR GI"}
print("| scene | mode | GPU frame ms | GI ms | specular ms | raw f136 | raw mean of 16 | mean/ref f136 | mean/ref, mean of 16 | factor vs path GI, GI ms | factor, (GI + specular) ms |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for s in ("cornell_box", "interior"):
    base_gi = ind[(s, "p", "1")][0] * gi[(s, "p")]
    base = ind[(s, "p", "1")][0] * (gi[(s, "p")] + spec[(s, "p")])
    for b in ("p", "c", "r"):
        e1, r1 = ind[(s, b, "1")]
        e16, r16 = ind[(s, b, "16")]
        t = gi[(s, b)] + spec[(s, b)]
        print(f"| {s} | {names[b]} | {frame[(s, b)]:.3f} | {gi[(s, b)]:.3f} | {spec[(s, b)]:.3f} | {e1:.2f} | {e16:.3f} | "
              f"{r1:.4f} | {r16:.4f} | {base_gi / (e1 * gi[(s, b)]):.2f} | {base / (e1 * t):.2f} |")
