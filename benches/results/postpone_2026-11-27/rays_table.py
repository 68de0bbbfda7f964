#!/usr/bin/env python3
"""Table of `run.sh rays`' JSON lines: per case and preset, each binary's median over reps of
the primary and primary+hemisphere GPU ms (bench-rays' medians of 200 frames)."""
import json, sys
from statistics import median

rows = {}
bins = []
for line in open(sys.argv[1]):
    d = json.loads(line)
    if d["bin"] not in bins:
        bins.append(d["bin"])
    key = (d["case"], d["preset"], d.get("traversal", ""))
    rows.setdefault(key, {}).setdefault(d["bin"], []).append((d["primary_ms"], d["ao_ms"], d["ao_grays_per_s"]))
base = bins[0]
print("| case | preset | traversal | " + " | ".join(f"{b} AO ms (G rays/s)" for b in bins) + " |")
print("|---|---|---|" + "---|" * len(bins))
for (case, preset, trav), per in rows.items():
    cells = []
    b0 = median(x[1] for x in per[base]) if base in per else None
    for b in bins:
        if b not in per:
            cells.append("-")
            continue
        ao = median(x[1] for x in per[b])
        g = median(x[2] for x in per[b])
        rel = f" {100 * (ao / b0 - 1):+.1f}%" if b0 and b != base else ""
        cells.append(f"{ao:.3f} ({g:.2f}){rel}")
    print(f"| {case} | {preset} | {trav} | " + " | ".join(cells) + " |")
