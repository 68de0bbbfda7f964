#!/usr/bin/env python3
"""A quality table (crates/solari-renderer/data/quality_h100.csv's format) with the error of
every (scene, setting) that RESULTS_DIR re-measured (its *_error.compare.json) replaced, and
the moving camera's error (its *_orbitN.compare.json, the orbit phase: the mean relMSE over
the frames N measured) in a rel_mse_moving column, added where the table has none; where the
compares hold the reference's noise (`--reference-variance`, sweep_phases.sh since the
forty-fourth session), it goes to reference_noise / reference_noise_moving the same way. The
comment lines are kept and one is added naming the re-measured rows.
Usage: quality_merge.py TABLE.csv RESULTS_DIR [NOTE] > NEW.csv"""
import json, os, re, sys

table, r = sys.argv[1], sys.argv[2]
note = sys.argv[3] if len(sys.argv) > 3 else ""
new = {}
orbit = {}
noise, orbit_noise = {}, {}


def noise_of(compare):
    return ((compare.get("reference_noise") or {}).get("all") or {}).get("rel_mse")


for f in os.listdir(r):
    m = re.match(r"^(.*)_orbit\d+\.compare\.json$", f)
    if m:
        for s in ("cornell_box", "sun_boxes", "many_lights", "interior"):
            if m.group(1).startswith(s + "_"):
                c = json.load(open(os.path.join(r, f)))
                key = (s, m.group(1)[len(s) + 1:])
                orbit.setdefault(key, []).append(c["all"]["rel_mse"])
                if noise_of(c) is not None:
                    orbit_noise.setdefault(key, []).append(noise_of(c))
    if f.endswith("_error.compare.json"):
        stem = f[: -len("_error.compare.json")]
        for s in ("cornell_box", "sun_boxes", "many_lights", "interior"):
            if stem.startswith(s + "_"):
                c = json.load(open(os.path.join(r, f)))
                new[(s, stem[len(s) + 1:])] = c["all"]["rel_mse"]
                if noise_of(c) is not None:
                    noise[(s, stem[len(s) + 1:])] = noise_of(c)
lines = open(table).read().splitlines()
out, header = [], None
for line in lines:
    if line.startswith("#"):
        out.append(line)
        continue
    if header is None:
        header = line.split(",")
        for column, wanted in (("rel_mse_moving", orbit), ("reference_noise", noise),
                               ("reference_noise_moving", orbit_noise)):
            if wanted and column not in header:
                header.append(column)
                line += "," + column
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
    while len(cells) < len(header):
        cells.append("")
    if key in orbit:
        cells[header.index("rel_mse_moving")] = f"{sum(orbit[key]) / len(orbit[key]):.6g}"
    if key in noise:
        cells[header.index("reference_noise")] = f"{noise[key]:.6g}"
    # The moving noise only where every frame of rel_mse_moving's mean had it.
    if key in orbit_noise and len(orbit_noise[key]) == len(orbit.get(key, [])):
        cells[header.index("reference_noise_moving")] = f"{sum(orbit_noise[key]) / len(orbit_noise[key]):.6g}"
    out.append(",".join(cells))
print("\n".join(out))
