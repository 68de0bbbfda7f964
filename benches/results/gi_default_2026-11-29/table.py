# Tables of this folder's runs: python3 table.py (run from this folder).
# GI ms and GPU frame ms are medians of time/'s two reps (GI = every pass named gi_*); relMSE
# is against the 4096-spp reference; "floor" is that reference's own noise term, estimated as
# relMSE(1024 spp, 4096 spp) / 3 (nested samples: the 1024-spp image's noise term v, the
# two differ by 3v/4, the 4096-spp image's is v/4); "excess" is relMSE - floor.
import csv, glob, json, re, statistics, tarfile, io, collections, sys
sys.path.insert(0, '..')
import ab_runs
times = {k: [(ab_runs.gi_ms(j), j['gpu_frame_ms'], j['wall_frame_ms']) for j in v]
         for k, v in ab_runs.runs_in_tarball('time/time.tar.gz').items()}
med = lambda k, i: statistics.median(x[i] for x in times[k])
rows = []
for f in glob.glob('still/*/still.csv'):
    rows += list(csv.DictReader(open(f)))
floor = {r['scene']: float(r['rel_mse']) / 3 for r in rows if r['binary'] == 'ref1024'}
scenes = ['cornell_box', 'sun_boxes', 'many_lights', 'interior']
print('## still camera, fallback denoiser (relMSE x1e3: frame 8 / frame 136 / mean of 121-136; excess = mean - floor)')
print('| scene | mode | GI ms | GPU frame ms | frame 8 | frame 136 | mean of 16 | floor | excess | mean/ref |')
print('|---|---|---|---|---|---|---|---|---|---|')
for s in scenes:
    for b in 'p ph p2 p4 r rh rq'.split():
        e = {(r['frames'], r['mean_of']): r for r in rows if r['scene'] == s and r['binary'] == b and r['denoiser'] == 'fallback'}
        if not e: continue
        m = float(e[('136', '16')]['rel_mse'])
        print(f"| {s} | {b} | {med((s,b),0):.3f} | {med((s,b),1):.3f} | {1e3*float(e[('8','1')]['rel_mse']):.3f} | "
              f"{1e3*float(e[('136','1')]['rel_mse']):.3f} | {1e3*m:.3f} | {1e3*floor[s]:.3f} | {1e3*(m-floor[s]):.3f} | {float(e[('136','16')]['mean_ratio']):.4f} |")
print()
print('## still camera, no denoiser, frame 136 (relMSE)')
print('| scene | mode | GI ms | relMSE | mean/ref |')
print('|---|---|---|---|---|')
for r in rows:
    if r['denoiser'] == 'none':
        print(f"| {r['scene']} | {r['binary']} | {med((r['scene'], r['binary']), 0):.3f} | {float(r['rel_mse']):.4f} | {float(r['mean_ratio']):.4f} |")
print()
o = list(csv.DictReader(open('orbit/orbit.csv')))
ofl = {(r['scene'], r['frame']): float(r['rel_mse']) / 3 for r in o if r['binary'] == 'ref1024'}
print('## orbit camera, fallback denoiser (relMSE x1e3 against the frame\'s 4096-spp reference; excess = relMSE - floor)')
print('| scene | mode | frame 32 | excess 32 | frame 96 | excess 96 |')
print('|---|---|---|---|---|---|')
for s in scenes:
    for b in 'p ph r rh rq'.split():
        e = {r['frame']: float(r['rel_mse']) for r in o if r['scene'] == s and r['binary'] == b}
        print(f"| {s} | {b} | {1e3*e['32']:.3f} | {1e3*(e['32']-ofl[(s,'32')]):.3f} | {1e3*e['96']:.3f} | {1e3*(e['96']-ofl[(s,'96')]):.3f} |")
    print(f"| {s} | floor | {1e3*ofl[(s,'32')]:.3f} | | {1e3*ofl[(s,'96')]:.3f} | |")
