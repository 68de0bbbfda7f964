cd /tmp/sbl
for v in lambert lifted; do
  /tmp/solari_base render /tmp/sbl/$v.gltf --mode reference --min-bounces 2 --spp 256 --pixel-centre --size 320x180 --out ref_$v.exr --variance-out var_$v.exr > /dev/null 2>&1
  /tmp/solari_life1000 render /tmp/sbl/$v.gltf --mode realtime --view indirect --denoiser none --size 320x180 --frames 136 --mean-of 16 --out m_$v.exr > /dev/null 2>&1
  python3 - $v <<'P'
import OpenEXR, numpy as np, sys
v=sys.argv[1]
def load(p):
    ch=OpenEXR.File(p).channels()
    rgb = ch["RGB"].pixels if "RGB" in ch else np.stack([ch[c].pixels for c in "RGB"], -1)
    return rgb.astype(np.float64).mean(-1)
r=load('ref_%s.exr'%v); m=load('m_%s.exr'%v)
h,w=r.shape; bh,bw=h//9,w//16
near=np.zeros(r.shape,bool); near[4*bh:7*bh,4*bw:9*bw]=True
print(v, "all %.4f  near-sphere blocks %.4f  elsewhere %.4f" % (m.sum()/r.sum(), m[near].sum()/r[near].sum(), m[~near].sum()/r[~near].sum()))
P
done
