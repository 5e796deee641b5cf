"""Coverage of the fit's intervals: many synthetic tables per setting, fitted like users do.

Run:  .venv/bin/python -m validation interval_coverage --tables 400 [--workers 2] [--out DIR]
      .venv/bin/python -m validation interval_coverage --summary DIR

Settings (studies/cross_nathan_2006.toml, 60 rows a table, truth e* = 0.6, mu = 0.15, where
part of the drops slide so that mu is measurable; noise 5 % on speed, 3 deg on angle, 10 %
on spin):

  a  e*, mu free; the impact parameter b written exactly (the setting of
     validation/injection_recovery.py)
  b  as a, with 2 mm of error on b (the table has b + noise and impact_parameter_err)
  c  as a, with 5 mm of error on b
  d  e*, mu, e_x free, tables made with e_x = 0.16 (Cross & Nathan's tangential restitution)
  g  a game (studies/game_fastball.toml, 100 rows): e* (at the reference speed) and e_x free,
     truth 0.5 and 0.3; Statcast-like rows (launch speed 1 %, launch and spray angle 1 deg,
     spin rate 10 %) with each row's pitch speed, bat speed, attack angle and an undercut
     measured to 2 mm

Table k of every setting is `synthesize(..., seed=1000 + k)` and its fit uses `seed=k`.
Each fit (mcbat.stats.fit.estimate.fit, profile-likelihood intervals) appends one JSON line to
DIR/<setting>.<worker>.jsonl, so an interrupted run keeps what it did and a rerun skips the
tables already done. The summary reports, per setting and parameter, the 1-sigma coverage
(the truth inside the profile interval [value - lower_error, value + upper_error]) with its
binomial standard error, the mean pull (value - truth over the error on the truth's side)
and its standard error, the pull's standard deviation, and chi2/dof against its expected
spread sqrt(2/dof).
"""

import argparse
import json
import math
import multiprocessing
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SETTINGS = {
    "a": {"truth": {"e": 0.6, "mu": 0.15}, "synth": {}},
    "b": {"truth": {"e": 0.6, "mu": 0.15}, "synth": {"impact_parameter_noise": 0.002}},
    "c": {"truth": {"e": 0.6, "mu": 0.15}, "synth": {"impact_parameter_noise": 0.005}},
    "d": {"truth": {"e": 0.6, "mu": 0.15, "e_x": 0.16}, "synth": {}},
    "g": {"truth": {"e": 0.5, "e_x": 0.3}, "synth": {"input_noise": {"undercut": 0.002}},
          "study": "game_fastball.toml", "rows": 100},
}


def one(setting, k, studies):
    from mcbat.stats.fit.estimate import fit
    from mcbat.stats.measurements import synthesize

    spec = SETTINGS[setting]
    study = studies[spec.get("study", "cross_nathan_2006.toml")]
    table = synthesize(study, spec.get("rows", 60), seed=1000 + k, **spec["truth"],
                       **spec["synth"])
    t0 = time.perf_counter()
    r = fit(study, table, tuple(spec["truth"]), seed=k)
    return {"setting": setting, "table": k, "seconds": time.perf_counter() - t0,
            "chi2": r.chi2, "dof": r.dof, "truth": spec["truth"],
            "params": r.to_dict()["params"]}


def worker(args):
    index, workers, tables, settings, out = args
    from mcbat.study import load_study

    studies = {name: load_study(ROOT / "studies" / name)
               for name in ("cross_nathan_2006.toml", "game_fastball.toml")}
    done = set()
    for path in Path(out).glob("*.jsonl"):
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            done.add((rec["setting"], rec["table"]))
    for k in range(index, tables, workers):  # table-major: every setting advances together
        for setting in settings:
            if (setting, k) in done:
                continue
            rec = one(setting, k, studies)
            with open(Path(out) / f"{setting}.{index}.jsonl", "a") as handle:
                handle.write(json.dumps(rec) + "\n")


def pull(entry, truth):
    """(value - truth) / the error on the truth's side; None if no interval there."""
    value = entry["value"]
    err = entry["upper_error"] if truth > value else entry["lower_error"]
    if entry.get("status") != "measured" or not err:
        return None
    return (value - truth) / err


def summary(out, log=print):
    recs = {}
    for path in sorted(Path(out).glob("*.jsonl")):
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            recs[(rec["setting"], rec["table"])] = rec
    rows = []
    for setting in SETTINGS:
        these = [r for (s, _), r in sorted(recs.items()) if s == setting]
        if not these:
            continue
        n = len(these)
        red = np.array([r["chi2"] / r["dof"] for r in these])
        dof = these[0]["dof"]
        secs = np.array([r["seconds"] for r in these])
        for p, truth in these[0]["truth"].items():
            pulls = [pull(r["params"][p], truth) for r in these]
            bad = sum(x is None for x in pulls)
            pv = np.array([x for x in pulls if x is not None])
            cover = (np.abs(pv) <= 1.0).sum() / n  # a table without an interval: not covered
            row = {"setting": setting, "param": p, "tables": n, "coverage": cover,
                   "coverage_se": math.sqrt(0.68 * 0.32 / n), "mean_pull": pv.mean(),
                   "mean_pull_se": pv.std(ddof=1) / math.sqrt(len(pv)),
                   "pull_std": pv.std(ddof=1), "no_interval": bad,
                   "chi2_dof_mean": red.mean(), "chi2_dof_expected_sd": math.sqrt(2 / dof),
                   "chi2_dof_sd": red.std(ddof=1), "median_seconds": float(np.median(secs))}
            rows.append(row)
            log(f"{setting} {p:4s} tables {n:4d}  coverage {100 * cover:5.1f} % "
                f"(+-{100 * row['coverage_se']:.1f})  mean pull {row['mean_pull']:+.3f} "
                f"(+-{row['mean_pull_se']:.3f})  pull sd {row['pull_std']:.2f}  "
                f"no interval {bad}  chi2/dof {red.mean():.3f} (sd {red.std(ddof=1):.3f}, "
                f"expected 1 +- {math.sqrt(2 / dof):.3f})  {np.median(secs):.1f} s/fit")
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=400)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--settings", default="abcdg")
    parser.add_argument("--out", default="coverage-results")
    parser.add_argument("--summary", metavar="DIR", help="only summarise DIR")
    args = parser.parse_args(argv)
    if args.summary:
        summary(args.summary)
        return
    Path(args.out).mkdir(parents=True, exist_ok=True)
    jobs = [(i, args.workers, args.tables, args.settings, args.out)
            for i in range(args.workers)]
    if args.workers == 1:
        worker(jobs[0])
    else:
        with multiprocessing.get_context("spawn").Pool(args.workers) as pool:
            pool.map(worker, jobs)
    summary(args.out)


if __name__ == "__main__":
    sys.exit(main())
