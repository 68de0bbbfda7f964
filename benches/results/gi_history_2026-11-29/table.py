"""The tables of benches/RESULTS.md's "The spatial merge as history" section. Call 1 (h200_1/):
GI alone, raw (`--view indirect --denoiser none`), relMSE x 10^3 without the reference's noise,
frame 136 and the mean of frames 121-136, with the GI passes' GPU ms at 1920x1080 (medians of
two reps; ro16's and rob's passes are ro's and rb's, which differ only in uniforms) and the
product relMSE x ms against one-candidate path GI's. Call 2 (h200_2/): the lit frame with the
fallback denoiser against a full-bounce reference (relMSE x 10^3 without its noise), and the
orbit camera's relMSE at frames 32 and 96. Call 3 (h200_3/): the own share's cost, the spatial
pass with the own sample evaluated again (`rold`) and read from the merge's terms (`rnew`),
medians of three reps. Usage: python3 table.py"""
import csv, os, statistics, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
import ab_runs  # noqa: E402 (benches/results/ab_runs.py)


def runs(folder):
    return ab_runs.runs_in_tarball(os.path.join(here, folder, "time.tar.gz"))


def rows(folder, name):
    return list(csv.DictReader(open(os.path.join(here, folder, name))))


names = {"p": "path GI", "r": "ReSTIR GI (defaults)", "ro": "ReSTIR GI, own history",
         "ro16": "own history, confidence cap 16", "rb": "ReSTIR GI, two rays, both shaded",
         "rob": "two rays, both shaded, own history"}
gi = {k: statistics.median(ab_runs.gi_ms(j) for j in v) for k, v in runs("h200_1").items()}
for s in ("cornell_box", "interior"):
    gi[(s, "rob")] = gi[(s, "rb")]
    gi[(s, "ro16")] = gi[(s, "ro")]
err = {(r["scene"], r["binary"], r["mean_of"]): 1e3 * float(r["rel_mse_excess"]) for r in rows("h200_1", "indirect.csv")}
print("| scene | mode | GI ms | raw f136 | raw mean of 16 | f136 × ms | factor vs path GI |")
print("|---|---|---|---|---|---|---|")
for s in ("cornell_box", "interior"):
    base = err[(s, "p", "1")] * gi[(s, "p")]
    for b in ("p", "r", "ro", "ro16", "rb", "rob"):
        e1, e16, t = err[(s, b, "1")], err[(s, b, "16")], gi[(s, b)]
        print(f"| {s} | {names[b]} | {t:.3f} | {e1:.2f} | {e16:.3f} | {e1 * t:.2f} | {base / (e1 * t):.2f} |")

lit = {(r["scene"], r["binary"], r["mean_of"]): 1e3 * float(r["rel_mse_excess"]) for r in rows("h200_2", "lit.csv")}
orbit = {(r["scene"], r["binary"], r["frame"]): 1e3 * float(r["rel_mse"]) for r in rows("h200_2", "orbit.csv")}
print()
print("| scene | mode | lit f136 (fallback) | lit mean of 16 | orbit f32 | orbit f96 |")
print("|---|---|---|---|---|---|")
for s in ("cornell_box", "interior"):
    for b in ("p", "r", "ro", "ro16", "rb", "rob"):
        o = [orbit.get((s, b, f)) for f in ("32", "96")]
        o = [f"{x:.3f}" if x is not None else "" for x in o]
        print(f"| {s} | {names[b]} | {lit[(s, b, '1')]:.4f} | {lit[(s, b, '16')]:.4f} | {o[0]} | {o[1]} |")

print()
print("| scene | pass | own sample evaluated again | read from the merge's terms | change |")
print("|---|---|---|---|---|")
t3 = runs("h200_3")
for s in ("cornell_box", "interior"):
    for p in ("gi_initial_temporal", "gi_spatial_shade"):
        a = statistics.median(j["passes"][p]["mean_ms"] for j in t3[(s, "rold")])
        b = statistics.median(j["passes"][p]["mean_ms"] for j in t3[(s, "rnew")])
        print(f"| {s} | {p} | {a:.4f} | {b:.4f} | {(b / a - 1) * 100:+.1f}% |")
