# Per-pass medians of an ab_passes_h200.sh run with any number of binaries (BINS), each
# against the first: python3 ab_variants.py EXTRACTED_AB_DIR "solari_base solari ..."
# (the world cache's upkeep passes and the light tiles' left out of the listing; a pass that a
# binary did not run shows as -, so every column stays that binary's).
import json,glob,statistics,collections,re,sys
root=sys.argv[1]; bins=sys.argv[2].split()
d=collections.defaultdict(lambda: collections.defaultdict(list)); mem={}
for f in sorted(glob.glob(root+'/ab_*.json')):
    # ab_SCENE_BINARY_REP.json: the binary is whichever of BINS ends the stem (longest first,
    # so `solari` does not take `x_solari`'s files); others are skipped.
    m=re.match(r'ab_(.+)_(\d+)\.json$',f.split('/')[-1])
    if not m: continue
    stem,rep=m.groups()
    b=next((x for x in sorted(bins,key=len,reverse=True) if stem.endswith('_'+x)),None)
    if b is None: continue
    s=stem[:len(stem)-len(b)-1]
    j=json.load(open(f))
    mem[(s,b)]=j['memory_bytes']['renderer_total']/2**20
    for k,v in j['passes'].items():
        if v['mean_ms'] is not None: d[(s,b)][k].append(v['mean_ms'])
    d[(s,b)]['GPU frame'].append(j['gpu_frame_ms']); d[(s,b)]['wall frame'].append(j['wall_frame_ms'])
# The four scenes of the first tables first, then any other scene the run holds.
first=['cornell_box','sun_boxes','many_lights','interior']
for s in first+sorted({k[0] for k in d}-set(first)):
    if not any((s,b) in d for b in bins): continue
    print(f"## {s}: memory " + "  ".join(f"{b} {mem.get((s,b),0):.1f}" for b in bins))
    every=set().union(*(d[(s,b)].keys() for b in bins))
    keys=sorted(k for k in every if not (k.startswith('world_cache') and k!='world_cache_gi') and k!='light_tiles')
    for k in keys:
        base=d[(s,bins[0])].get(k)
        base=statistics.median(base) if base else None
        row=f"{s:12s} {k:20s} " + (f"{base:8.4f}" if base else f"{'-':>8s}")
        for b in bins[1:]:
            v=d[(s,b)].get(k)
            if v and base:
                v=statistics.median(v); row+=f" {v:8.4f} ({100*(v/base-1):+5.1f}%)"
            elif v:
                row+=f" {statistics.median(v):8.4f} {'':9s}"
            else:
                row+=f" {'-':>8s} {'':9s}"
        print(row)
