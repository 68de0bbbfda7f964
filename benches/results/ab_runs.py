"""Shared by the result folders' table scripts: the runs of an `ab_passes_h200.sh` time
tarball (each run's `--json`, `ab_SCENE_BINARY_REP.json`) and their GI passes' GPU ms, and the
rows of `gi_indirect_2026-11-29/run.sh`'s error CSVs."""
import csv, json, os, re, tarfile


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


def error_rows(path, by="mean_of"):
    """{(scene, binary, row[by]): row} of an error CSV written by
    `gi_indirect_2026-11-29/run.sh` (`indirect.csv`, `lit.csv`): each row's fields as strings,
    `rel_mse_excess` the relMSE without the reference's noise. `by="frames"` keys runs of one
    frame count each (RUNS="136:1 500:1 ...")."""
    with open(path) as f:
        return {(r["scene"], r["binary"], r[by]): r for r in csv.DictReader(f)}
