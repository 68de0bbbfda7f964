"""Shared by the result folders' table scripts: the runs of an `ab_passes_h200.sh` time
tarball (each run's `--json`, `ab_SCENE_BINARY_REP.json`) and their GI passes' GPU ms."""
import json, os, re, tarfile


def runs_in_tarball(path):
    """{(scene, binary): [run's JSON, ...]} for every `ab_*.json` in the tarball at `path`."""
    runs = {}
    with tarfile.open(path) as t:
        for m in t.getmembers():
            g = re.match(r"ab_(.+)_(\w+)_(\d+)\.json$", os.path.basename(m.name))
            if g:
                runs.setdefault(g.groups()[:2], []).append(json.load(t.extractfile(m)))
    return runs


def passes_ms(run, prefixes):
    """The summed mean GPU ms of a run's passes whose names start with any of `prefixes`
    (those that ran)."""
    return sum(v["mean_ms"] for k, v in run["passes"].items()
               if k.startswith(tuple(prefixes)) and v["mean_ms"] is not None)


def gi_ms(run):
    """The summed mean GPU ms of a run's passes named gi_* (those that ran)."""
    return passes_ms(run, ("gi",))
