# Per-pass medians of an ab_passes_h200.sh run: python3 ab_per_pass.py DIR "scene ..."
# (DIR holds ab_SCENE_BIN_REP.json; base solari_base, new solari; exact names, so
# solari_base files never count as solari).
import json,glob,statistics,sys,re
root=sys.argv[1]; scenes=sys.argv[2].split()
for s in scenes:
    rows={}
    for b in ['solari_base','solari']:
        P={}
        for f in glob.glob(f'{root}/ab_{s}_{b}_*.json'):
            if not re.fullmatch(rf'.*/ab_{s}_{b}_\d+\.json',f): continue
            d=json.load(open(f))
            for k,v in d['passes'].items():
                if v['mean_ms'] is not None: P.setdefault(k,[]).append(v['mean_ms'])
            P.setdefault('_frame',[]).append(d['gpu_frame_ms']); P.setdefault('_wall',[]).append(d['wall_frame_ms'])
        rows[b]={k:statistics.median(v) for k,v in P.items()}
    print(s)
    for k in sorted(rows['solari']):
        a=rows['solari_base'].get(k); n=rows['solari'][k]
        print(f"  {k:22s} {a:.4f} -> {n:.4f} ({(n/a-1)*100:+.1f}%)")
