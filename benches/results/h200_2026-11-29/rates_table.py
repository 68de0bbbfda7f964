#!/usr/bin/env python3
"""GI at full, half and quarter rate as plot-gi's table (forty-second session): GPU frame ms from
quarter/time.tar.gz's table (phase1/ for ReSTIR GI at a quarter on the Cornell box and interior)
and relMSE of frame 136 and of the mean of frames 121-136 from the kernel_error.csv files.
Usage: python3 rates_table.py > rates_table.csv; then
cargo run -p solari-benches --bin plot-gi -- rates_table.csv rates_time_error.png"""
import csv, os, re

HERE = os.path.dirname(os.path.abspath(__file__))
MODES = {"solari": "path+spec", "solari_rh": "restir+spec+half", "solari_rq": "restir+spec+quarter",
         "solari_pq": "path+spec+quarter"}


def frame_ms(path):
    """{(scene, binary): (GPU frame ms, gi ms)} from an ab_variants.py table."""
    out, order = {}, {}
    for line in open(path):
        m = re.match(r"## (\S+): memory (.*)", line)
        if m:
            bins = re.findall(r"(\S+) [\d.]+", m.group(2))
            order[m.group(1)] = bins
            continue
        parts = line.split()
        if len(parts) < 3 or parts[0] not in order:
            continue
        scene, name = parts[0], " ".join(parts[1:3]) if parts[1] == "GPU" else parts[1]
        values = [float(v) for v in re.findall(r"(?<![(+\-\d.])(\d+\.\d+)(?! ?%)", line)]
        for b, v in zip(order[scene], values):
            out.setdefault((scene, b), {})[name] = v
    return out


def errors(path):
    e = {}
    for r in csv.DictReader(open(path)):
        e[(r["scene"], r["binary"], r["frames"], r["mean_of"])] = r
    return e


times = frame_ms(os.path.join(HERE, "quarter/time_table.txt"))
times.update({k: v for k, v in frame_ms(os.path.join(HERE, "phase1/time_table.txt")).items()
              if k[1] == "solari_rq"})
err = errors(os.path.join(HERE, "quarter/kernel_error.csv"))
err.update({k: v for k, v in errors(os.path.join(HERE, "phase1/kernel_error.csv")).items()})
print("scene,mode,gpu_ms,di_ms,gi_ms,specular_ms,rel_mse_1,rel_mse_16,flip_1,mean_ratio_1")
for scene in ["cornell_box", "sun_boxes", "many_lights", "interior"]:
    for b, mode in MODES.items():
        t = times[(scene, b)]
        one, mean = err[(scene, b, "136", "1")], err[(scene, b, "136", "16")]
        di = t.get("di_initial_temporal", 0) + t.get("di_spatial_shade", 0)
        gi = t.get("gi_initial_temporal", 0) + t.get("gi_spatial_shade", 0)
        print(f"{scene},{mode},{t['GPU frame']},{di},{gi},{t.get('specular_gi', 0)},"
              f"{one['rel_mse']},{mean['rel_mse']},{one['flip']},{one['mean_ratio']}")
