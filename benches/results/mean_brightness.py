"""Each image's mean over the reference's (EXR, RGB or RGBA; the first three channels), as
the lavapipe probe scripts print it. Usage: python3 mean_brightness.py REF IMG...
(pip install OpenEXR numpy)"""
import sys

import numpy as np
import OpenEXR


def load(p):
    ch = OpenEXR.File(p).channels()
    k = 'RGB' if 'RGB' in ch else 'RGBA'
    return ch[k].pixels[..., :3].astype(np.float64)


ref = load(sys.argv[1])
for p in sys.argv[2:]:
    print(p, "mean brightness %.4f of the reference's" % (load(p).mean() / ref.mean()))
