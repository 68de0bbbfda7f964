# Furnace_sphere rows of an ab_passes_h200.sh run (ab_variants.py tables the four main scenes
# only). Usage: python3 furnace_table.py UNPACKED_DIR "BIN ..."
import json,glob,statistics,sys
d, bins = sys.argv[1], sys.argv[2].split()
print("furnace_sphere, `--denoiser fallback` (path GI), 1920x1080, 300 frames, medians of two reps, ms")
print("| binary | GPU frame | gi_initial_temporal | di_spatial_shade | wall frame |")
print("|---|---|---|---|---|")
for b in bins:
    g=[json.load(open(f)) for f in sorted(glob.glob(f'{d}/*furnace_sphere_{b}_[0-9].json'))]
    m=lambda k: round(statistics.median([x['passes'][k]['mean_ms'] for x in g]),3)
    print(f"| {b} | {round(statistics.median([x['gpu_frame_ms'] for x in g]),3)} | {m('gi_initial_temporal')} | {m('di_spatial_shade')} | {round(statistics.median([x['wall_frame_ms'] for x in g]),3)} |")
