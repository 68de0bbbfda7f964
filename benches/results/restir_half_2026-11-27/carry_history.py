# The experiment of benches/RESULTS.md, "ReSTIR GI from half the pixels" (not kept): run from
# the repository root on the commit that shipped half-rate ReSTIR GI; it edits pixel_gi.
p='crates/solari-restir/shaders/restir_gi_initial.wesl'
s=open(p).read()
old="""    var r = gi_empty();
    r.confidence = 1.0;
    if traced {
        r = initial_sample(p, &rng);
        r.weight *= scale;
    }"""
assert old in s
s=s.replace(old,"""    var r = gi_empty();
    // Experiment: with reuse, an untraced pixel carries its history whole (confidence 0)
    // and a traced one keeps weight 1.
    r.confidence = select(1.0, 0.0, GI_REUSE);
    if traced {
        r = initial_sample(p, &rng);
        r.weight *= select(scale, 1.0, GI_REUSE);
    }""")
open(p,'w').write(s)
