#!/usr/bin/env python3
"""Left-one-out check of rules that guess a scene's error table from the other scenes': for
each scene of a sweep table (quality_table.py's CSV) and each budget, the setting with the
least guessed error among those whose measured GPU ms fit, judged by its measured error
against the best fitting setting's. A rule combines the other scenes' errors per setting,
each as a multiple of its scene's best. Usage: quality_rules.py sweep_table.csv [BUDGETS]."""
import csv, math, statistics, sys

rows = [r for r in csv.DictReader(open(sys.argv[1])) if not r["setting"].startswith("auto")]
budgets = [float(b) for b in (sys.argv[2:] or ["4", "8", "16"])]
data = {}
for r in rows:
    data.setdefault(r["scene"], {})[r["setting"]] = (float(r["gpu_ms"]), float(r["rel_mse"]))
scenes = sorted(data)
multiple = {s: {g: v[1] / min(x[1] for x in data[s].values()) for g, v in data[s].items()}
            for s in scenes}
rules = {
    "worst": max,
    "mean": lambda xs: sum(xs) / len(xs),
    "geometric mean": lambda xs: math.exp(sum(map(math.log, xs)) / len(xs)),
    "median": statistics.median,
    "rms": lambda xs: math.sqrt(sum(x * x for x in xs) / len(xs)),
}
print("rule, cells within 10% of the best fitting, mean and largest multiple of it")
for name, combine in rules.items():
    ratios = []
    for s in scenes:
        others = [o for o in scenes if o != s]
        guess = {g: combine([multiple[o][g] for o in others])
                 for g in data[s] if all(g in multiple[o] for o in others)}
        for b in budgets:
            fit = [g for g in guess if data[s][g][0] <= b]
            if not fit:
                continue
            pick = min(fit, key=lambda g: (guess[g], data[s][g][0]))
            ratios.append(data[s][pick][1] / min(data[s][g][1] for g in fit))
    ok = sum(r <= 1.1 for r in ratios)
    print(f"{name}, {ok}/{len(ratios)}, {sum(ratios) / len(ratios):.3f}, {max(ratios):.3f}")
