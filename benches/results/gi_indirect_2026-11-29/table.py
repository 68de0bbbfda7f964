# Tables of this folder's runs: python3 table.py > table.md (run from this folder).
# GI ms: the forty-fourth session's medians at 1920x1080 (../gi_default_2026-11-29/time: the
# same GI passes; the adaptive cap's stop costs nothing). relMSE x1e3 at 960x540 with each
# reference's own noise taken out (compare --reference-variance), frame 136 of a still camera
# and the mean of frames 121-136; raw frames (--denoiser none) against --pixel-centre
# references, denoised (fallback) against jittered ones, 4096 paths each.
# "new": the adaptive cap stops on settled views (4d1c202); "old": always on (3415810, and the
# N wrappers: --gi-adaptive-cap-settle never).
import csv, json, re, statistics, tarfile, collections, math, sys
sys.path.insert(0, '..')
import ab_runs
runs = ab_runs.runs_in_tarball('../gi_default_2026-11-29/time/time.tar.gz')
gi_ms = lambda s, b: statistics.median(ab_runs.gi_ms(j) for j in runs[(s, b.rstrip('N'))])
def load(path, tag, rename=None):
    out = {}
    for r in csv.DictReader(open(path)):
        b = r['binary']
        out[(tag, r['scene'], b, r['denoiser'], r['mean_of'])] = r
    return out
ind = {}; ind.update(load('h200_1/indirect.csv', 'old')); ind.update(load('h200_2/indirect.csv', 'new'))
# Call 6 (867721f): sun_boxes and many_lights, path GI ('old' as in call 1: the cap does not
# touch it) and ReSTIR GI with the cap's stop ('new').
for k, r in load('h200_6/indirect.csv', 'new').items():
    ind[k] = r
    if k[2].startswith('p'):
        ind[('old',) + k[1:]] = r
lit = {}; lit.update(load('h200_2/lit.csv', 'new')); lit.update(load('h200_4/lit.csv', 'new'))
x = lambda r: 1e3 * float(r['rel_mse_excess'])
scenes = ['cornell_box', 'interior']
def table(title, data, rows, scenes=scenes):
    print(f'## {title}')
    print('| scene | mode | GI ms | raw f136 | raw mean of 16 | denoised f136 | denoised mean of 16 | raw f136 mean/ref |')
    print('|---|---|---|---|---|---|---|---|')
    for s in scenes:
        for tag, b in rows:
            k = lambda d, m: data[(tag, s, b, d, m)]
            if (tag, s, b, 'none', '1') not in data: continue
            name = b if tag == 'new' or b.startswith('p') else b + ' (old)'
            print(f"| {s} | {name} | {gi_ms(s, b):.3f} | {x(k('none','1')):.3f} | {x(k('none','16')):.3f} | "
                  f"{x(k('fallback','1')):.3f} | {x(k('fallback','16')):.3f} | {float(k('none','1')['mean_ratio']):.4f} |")
    print()
table('GI alone: the indirect view against indirect references (relMSE x1e3 without the reference\'s noise)', ind,
      [('old', b) for b in 'p p2 p4 r rh rq'.split()] + [('new', b) for b in 'r rh rq'.split()],
      scenes + ['sun_boxes', 'many_lights'])
table('The lit frame against full references (relMSE x1e3 without the reference\'s noise)', lit,
      [('new', b) for b in 'p p2 p4 r rh rq rN rqN'.split()])
# Equal time: path GI's curve through 1, 2 and 4 candidates, log-log between neighbours (and
# extended past its ends by the nearest segment), read at a ReSTIR mode's GI ms.
def path_at(data, tag_path, s, d, m, t):
    pts = sorted((gi_ms(s, b), x(data[(tag_path, s, b, d, m)])) for b in ('p', 'p2', 'p4'))
    seg = pts[:2] if t <= pts[1][0] else pts[1:]
    (t0, e0), (t1, e1) = seg
    return math.exp(math.log(e0) + (math.log(e1) - math.log(e0)) * (math.log(t) - math.log(t0)) / (math.log(t1) - math.log(t0)))
print('## Equal GPU time: path GI (1, 2, 4 candidates) read at each ReSTIR mode\'s GI ms, over the mode\'s own error')
print('| scene | mode | GI ms | GI alone, raw f136 | lit raw f136 | lit denoised mean of 16 |')
print('|---|---|---|---|---|---|')
for s in scenes + ['sun_boxes', 'many_lights']:
    for tag, b in [('old', 'r'), ('old', 'rh'), ('old', 'rq'), ('new', 'r'), ('new', 'rh'), ('new', 'rq')]:
        if (tag, s, b, 'none', '1') not in ind: continue
        t = gi_ms(s, b)
        a = path_at(ind, 'old', s, 'none', '1', t) / x(ind[(tag, s, b, 'none', '1')])
        if tag == 'new' and (tag, s, b, 'none', '1') in lit:
            l1 = path_at(lit, 'new', s, 'none', '1', t) / x(lit[('new', s, b, 'none', '1')])
            l2 = path_at(lit, 'new', s, 'fallback', '16', t) / x(lit[('new', s, b, 'fallback', '16')])
            lit_cells = f'{l1:.2f}x | {l2:.2f}x'
        else:
            lit_cells = '| '
        print(f'| {s} | {b}{" (old)" if tag == "old" else ""} | {t:.3f} | {a:.2f}x | {lit_cells} |')
