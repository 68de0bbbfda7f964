#!/usr/bin/env python3
"""A quality table (crates/solari-renderer/data/quality_h100.csv's format) with the error of
every (scene, setting) that RESULTS_DIR re-measured (its *_error.compare.json) replaced; the
comment lines are kept and one is added naming the re-measured rows.
Usage: quality_merge.py TABLE.csv RESULTS_DIR [NOTE] > NEW.csv"""
import json, os, sys

table, r = sys.argv[1], sys.argv[2]
note = sys.argv[3] if len(sys.argv) > 3 else ""
new = {}
for f in os.listdir(r):
    if f.endswith("_error.compare.json"):
        stem = f[: -len("_error.compare.json")]
        for s in ("cornell_box", "sun_boxes", "many_lights", "interior"):
            if stem.startswith(s + "_"):
                new[(s, stem[len(s) + 1:])] = json.load(open(os.path.join(r, f)))["all"]["rel_mse"]
lines = open(table).read().splitlines()
out, header = [], None
for line in lines:
    if line.startswith("#"):
        out.append(line)
        continue
    if header is None:
        header = line.split(",")
        if new:
            out.append(f"# rel_mse re-measured for {', '.join(sorted({s for _, s in new}))}"
                       + (f" ({note})" if note else ""))
        out.append(line)
        continue
    cells = line.split(",")
    key = (cells[header.index("scene")], cells[header.index("setting")])
    if key in new:
        cells[header.index("rel_mse")] = f"{new[key]:.6g}"
    out.append(",".join(cells))
print("\n".join(out))
