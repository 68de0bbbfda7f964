import json,glob,re,sys,statistics as st
d0=sys.argv[1]; bins=sys.argv[2].split()
print("| scene | " + " | ".join(bins) + " |")
print("|---|" + "---|"*len(bins))
for s in "furnace_sphere interior cornell_box sun_boxes many_lights metal_rough_spheres furnace_uniform emissive_strength_test".split():
    g=[];fr=[]
    for b in bins:
        fs=sorted(f for f in glob.glob(f'{d0}/ab_{s}_{b}_*.json') if re.fullmatch(rf'.*/ab_{s}_{b}_\d+\.json',f))
        ds=[json.load(open(f)) for f in fs]
        g.append(st.median([d['passes']['gbuffer']['mean_ms'] for d in ds]))
        fr.append(st.median([d['gpu_frame_ms']['median'] if isinstance(d['gpu_frame_ms'],dict) else d['gpu_frame_ms'] for d in ds]))
    cells=[f"{g[0]:.3f} ({fr[0]:.3f})"]+[f"{x:.3f} ({100*(x/g[0]-1):+.1f}%; {f:.3f})" for x,f in zip(g[1:],fr[1:])]
    print(f"| {s} | "+" | ".join(cells)+" |")
