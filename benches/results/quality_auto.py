#!/usr/bin/env python3
"""Judges `--quality auto` against the full sweep (benches/results/quality_h200.sh output).
For each scene and budget: auto's pick (its own run's GPU ms, the sweep's time and error of
that setting), the setting with the least error among those whose swept time fits the budget,
and what auto would pick for a scene missing from its table (leave-one-out: each setting's
worst relative error over the other three scenes, with auto's own time predictions); then the
accuracy of the start-up time predictions against the sweep.
Usage: quality_auto.py ERROR_DIR TIME_AND_AUTO_DIR [SKIP scene:setting ...]
(SKIP: sweep timings to ignore in the prediction statistics, e.g. warm-up outliers)."""
import json, os, sys

err_dir, run_dir = sys.argv[1], sys.argv[2]
skip = {tuple(s.split(":")) for s in sys.argv[3:]}
SCENES = ["cornell_box", "sun_boxes", "many_lights", "interior"]
settings = sorted(f[len("cornell_box_"):-len("_error.compare.json")]
                  for f in os.listdir(err_dir)
                  if f.startswith("cornell_box_") and f.endswith("_error.compare.json"))
load = lambda d, f: json.load(open(os.path.join(d, f)))
err = {(s, g): load(err_dir, f"{s}_{g}_error.compare.json")["all"]["rel_mse"]
       for s in SCENES for g in settings}
tim = {(s, g): load(run_dir, f"{s}_{g}_time.json")["gpu_frame_ms"] for s in SCENES for g in settings}
rel = lambda s, g: err[(s, g)] / min(err[(s, h)] for h in settings)
print("| scene | budget ms | auto's pick | its GPU ms (auto run / sweep) | predicted ms | error × best fitting | best fitting setting (sweep ms) | unmeasured-scene pick | its error × best fitting | probe s |")
print("|---|---|---|---|---|---|---|---|---|---|")
hits, loo_hits, cells = 0, 0, 0
for s in SCENES:
    others = [o for o in SCENES if o != s]
    worst = {g: max(rel(o, g) for o in others) for g in settings}
    for b in (4, 8, 16):
        a = load(run_dir, f"{s}_auto{b}.json")
        q = a["quality"]
        pick, pred = q["chosen"], q["predicted_ms_per_setting"]
        fit = [g for g in settings if tim[(s, g)] <= b]
        best = min(fit, key=lambda g: err[(s, g)])
        fits_pred = [g for g in settings if pred[g] <= b]
        loo = min(fits_pred, key=lambda g: (worst[g], pred[g])) if fits_pred else min(settings, key=lambda g: pred[g])
        r, rl = err[(s, pick)] / err[(s, best)], err[(s, loo)] / err[(s, best)]
        cells += 1
        hits += r <= 1.1 and a["gpu_frame_ms"] <= b
        loo_hits += rl <= 1.1 and tim[(s, loo)] <= b
        print(f"| {s} | {b} | `{pick}` | {a['gpu_frame_ms']:.2f} / {tim[(s, pick)]:.2f} | {q['predicted_ms']:.2f} | "
              f"{r:.3f} | `{best}` ({tim[(s, best)]:.2f}) | `{loo}` | {rl:.3f} | {q['probe_s']:.2f} |")
print(f"\nwithin 10% of the best fitting setting, in budget: auto {hits}/{cells}, "
      f"unmeasured-scene rule {loo_hits}/{cells}")
e = []
for s in SCENES:
    pred = load(run_dir, f"{s}_auto16.json")["quality"]["predicted_ms_per_setting"]
    e += [(pred[g] / tim[(s, g)] - 1, s, g) for g in settings if (s, g) not in skip]
e.sort()
print(f"time predictions against the sweep ({len(e)} points): mean |error| "
      f"{sum(abs(x[0]) for x in e) / len(e):.1%}, from {e[0][0]:+.1%} ({e[0][1]} {e[0][2]}) "
      f"to {e[-1][0]:+.1%} ({e[-1][1]} {e[-1][2]})")
