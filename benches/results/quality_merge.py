#!/usr/bin/env python3
"""A quality table (crates/solari-renderer/data/quality_h100.csv's format) with the error of
every (scene, setting) that RESULTS_DIR re-measured (its *_error.compare.json) replaced, and
the moving camera's error (its *_orbitN.compare.json, the orbit phase: the mean relMSE over
the frames N measured) in a rel_mse_moving column, added where the table has none; the
comment lines are kept and one is added naming the re-measured rows.
Usage: quality_merge.py TABLE.csv RESULTS_DIR [NOTE] > NEW.csv"""
import json, os, re, sys

table, r = sys.argv[1], sys.argv[2]
note = sys.argv[3] if len(sys.argv) > 3 else ""
new = {}
orbit = {}
for f in os.listdir(r):
    m = re.match(r"^(.*)_orbit\d+\.compare\.json$", f)
    if m:
        for s in ("cornell_box", "sun_boxes", "many_lights", "interior"):
            if m.group(1).startswith(s + "_"):
                v = json.load(open(os.path.join(r, f)))["all"]["rel_mse"]
                orbit.setdefault((s, m.group(1)[len(s) + 1:]), []).append(v)
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
        if orbit and "rel_mse_moving" not in header:
            header.append("rel_mse_moving")
            line += ",rel_mse_moving"
        if orbit:
            frames = sorted({re.match(r"^.*_orbit(\d+)\.", f).group(1) for f in os.listdir(r)
                             if re.match(r"^.*_orbit\d+\.compare\.json$", f)}, key=int)
            out.append(f"# rel_mse_moving: mean relMSE of orbit frames {', '.join(frames)} at the same size, "
                       "each against a reference of that frame (PHASES=orbit)"
                       + (f" ({note})" if note else ""))
        if new:
            out.append(f"# rel_mse re-measured for {', '.join(sorted({s for _, s in new}))}"
                       + (f" ({note})" if note else ""))
        out.append(line)
        continue
    cells = line.split(",")
    key = (cells[header.index("scene")], cells[header.index("setting")])
    if key in new:
        cells[header.index("rel_mse")] = f"{new[key]:.6g}"
    if orbit:
        while len(cells) < len(header):
            cells.append("")
        if key in orbit:
            cells[header.index("rel_mse_moving")] = f"{sum(orbit[key]) / len(orbit[key]):.6g}"
    out.append(",".join(cells))
print("\n".join(out))
