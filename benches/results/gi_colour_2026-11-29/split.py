"""relMSE of EXR images against a reference, split (lavapipe probes, `lavapipe.sh`): per
channel as `solari compare` counts it (d^2 / (ref^2 + 0.01), the reference's variance taken
out), in luminance alone, and chroma alone (each pixel scaled to the reference's luminance).
Usage: python3 split.py REF.exr VAR.exr IMAGE.exr ...  (pip install OpenEXR numpy)"""
import OpenEXR, numpy as np, sys
def load(p):
    f = OpenEXR.File(p); ch = f.channels()
    if 'RGB' in ch: return ch['RGB'].pixels.astype(np.float64)
    if 'RGBA' in ch: return ch['RGBA'].pixels[..., :3].astype(np.float64)
    return np.stack([ch[c].pixels for c in 'RGB'], -1).astype(np.float64)
ref = load(sys.argv[1]); var = load(sys.argv[2])
w = np.array([0.2126, 0.7152, 0.0722])
for p in sys.argv[3:]:
    a = load(p)
    d = a - ref
    per = np.mean(d*d/(ref*ref+0.01)) - np.mean(var/(ref*ref+0.01))
    la, lr, lv = a@w, ref@w, var@(w*w)
    lum = np.mean((la-lr)**2/(lr*lr+0.01)) - np.mean(lv/(lr*lr+0.01))
    # chroma-only: image rescaled per pixel to reference luminance
    s = np.where(la > 1e-6, lr/np.maximum(la,1e-6), 1)[..., None]
    chrom = np.mean((a*s-ref)**2/(ref*ref+0.01))
    print(p, "per-channel %.5f  luminance %.5f  chroma-only %.5f" % (per, lum, chrom))
