"""The drop-test fit against tables it did not simulate: pulls, coverage, limits, refusals.

Run:  .venv/bin/python benchmarks/fit_validation.py --settings inside,edges --tables 400 \
          --workers 2 --out fit-validation
      .venv/bin/python benchmarks/fit_validation.py --summary fit-validation
      .venv/bin/python benchmarks/fit_validation.py --crosscheck 3

Tables come from mcbat.testing.drop_tables (the geometry, the draws and the noise written
out there, not the study machinery nor `mcbat synth`), fitted as a user would:
`fit(studies/cross_nathan_2006.toml, table, ("e", "mu"))` with profile intervals. Their
impacts are solved by the kernel, because the reference solver takes ~0.5 s an impact;
`--crosscheck N` makes N tables with both solvers from the same random numbers and prints
their largest difference over the measurement errors (the tables are the same to ~1e-8 of
an error), and `--solver reference` uses the reference for every table.

Settings (truth e* = 0.6; 5 mm of stated error on the impact parameter unless said; the
study's range of the impact parameter is +-1 in):

  inside    mu = 0.18, b uniform in +-2.54 cm, 60 rows
  edges     mu = 0.18, b within 0.5 cm of the ends of +-2.54 cm, 60 rows
  wide      mu = 0.18, b uniform in +-4 cm (beyond the study's range), 60 rows
  stick     mu = 0.5, most drops stick (mu bounded from below only), 60 rows
  slide     mu = 0.1, most drops slide, 60 rows
  small     mu = 0.18, 20 rows
  large     mu = 0.18, 3000 rows
  err1      mu = 0.18, 1 mm of error on b
  err10     mu = 0.18, 10 mm of error on b

Table k of a setting uses seed 1000 + k, its fit seed k. Each result is one JSON line in
DIR/<setting>.<worker>.jsonl, so an interrupted run keeps what it did. The summary gives,
per setting and parameter: tables, refusals (exit-2 errors), two-sided 68 % coverage of the
profile interval (a table without one counts as not covered), the mean pull and its
standard error, the share of tables reporting a one-sided 95 % limit and how often that
limit holds the truth, and zero-width intervals.
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
    "inside": {},
    "edges": {"edges": 0.005},
    "wide": {"impact_parameter": (-0.04, 0.04)},
    "stick": {"mu": 0.5},
    "slide": {"mu": 0.1},
    "small": {"rows": 20},
    "large": {"rows": 3000},
    "err1": {"impact_parameter_err": 0.001},
    "err10": {"impact_parameter_err": 0.010},
}
TRUTH = {"e": 0.6, "mu": 0.18}


def make_table(setting, k, solver):
    from mcbat.testing.drop_tables import drop_table, kernel_solver, reference_solver

    spec = {**TRUTH, **SETTINGS[setting]}
    rows = spec.pop("rows", 60)
    chosen = reference_solver if solver == "reference" else kernel_solver
    return drop_table(rows, 1000 + k, solver=chosen, **spec)


def one(setting, k, study, solver):
    from mcbat.errors import InputError
    from mcbat.stats.fit import fit

    table = make_table(setting, k, solver)
    truth = {p: table.attrs["truth"][p] for p in TRUTH}
    t0 = time.perf_counter()
    rec = {"setting": setting, "table": k, "truth": truth}
    try:
        r = fit(study, table, tuple(TRUTH), seed=k)
    except InputError as err:
        rec.update(refused=str(err), seconds=time.perf_counter() - t0)
        return rec
    out = r.to_dict()
    rec.update(seconds=time.perf_counter() - t0, chi2=r.chi2, dof=r.dof,
               params=out["params"], warnings=out["warnings"],
               widened=[k for k, v in out["input_priors"].items() if v["widened"]])
    return rec


def worker(args):
    index, workers, tables, settings, out, solver = args
    from mcbat.study import load_study

    study = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
    done = set()
    for path in Path(out).glob("*.jsonl"):
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            done.add((rec["setting"], rec["table"]))
    for k in range(index, tables, workers):  # table-major: every setting advances together
        for setting in settings:
            if (setting, k) in done:
                continue
            rec = one(setting, k, study, solver)
            with open(Path(out) / f"{setting}.{index}.jsonl", "a") as handle:
                handle.write(json.dumps(rec) + "\n")


def pull(entry, truth):
    """(value - truth) / the profile error on the truth's side; None without an interval."""
    if entry.get("status") != "measured":
        return None
    err = entry["upper_error"] if truth > entry["value"] else entry["lower_error"]
    return (entry["value"] - truth) / err if err else None


def limit_holds(entry, truth):
    """None if the entry is not a one-sided limit, else whether it holds the truth."""
    if entry.get("status") == "lower_limit":
        return truth >= entry["limit"]
    if entry.get("status") == "upper_limit":
        return truth <= entry["limit"]
    return None


def fmt(value, spec):
    return "-" if value is None else format(value, spec)


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
        fitted = [r for r in these if "refused" not in r]
        refused = len(these) - len(fitted)
        widened = sum(bool(r.get("widened")) for r in fitted)
        for p in TRUTH:
            entries = [(r["params"][p], r["truth"][p]) for r in fitted]
            pulls = [pull(e, t) for e, t in entries]
            pv = np.array([x for x in pulls if x is not None])
            limits = [limit_holds(e, t) for e, t in entries]
            limits = [x for x in limits if x is not None]
            zero = sum(1 for e, _ in entries if e.get("status") == "measured"
                       and (e.get("lower_error") == 0 or e.get("upper_error") == 0))
            n = max(len(fitted), 1)
            row = {"setting": setting, "param": p, "tables": len(these), "refused": refused,
                   "widened": widened, "coverage": float((np.abs(pv) <= 1).sum() / n),
                   "coverage_se": math.sqrt(0.68 * 0.32 / n),
                   "mean_pull": float(pv.mean()) if len(pv) else None,
                   "mean_pull_se": float(pv.std(ddof=1) / math.sqrt(len(pv)))
                   if len(pv) > 1 else None,
                   "pull_sd": float(pv.std(ddof=1)) if len(pv) > 1 else None,
                   "limits": len(limits),
                   "limit_coverage": float(np.mean(limits)) if limits else None,
                   "zero_width": zero,
                   "median_seconds": float(np.median([r["seconds"] for r in these]))}
            rows.append(row)
            log(f"{setting:7s} {p:3s} tables {len(these):4d} refused {refused:3d} widened "
                f"{widened:3d}  coverage {100 * row['coverage']:5.1f} % (+-"
                f"{100 * row['coverage_se']:.1f})  mean pull {fmt(row['mean_pull'], '+.3f')} "
                f"(+-{fmt(row['mean_pull_se'], '.3f')})  pull sd {fmt(row['pull_sd'], '.2f')}  "
                f"95 % limits {len(limits)} holding {fmt(row['limit_coverage'], '.3f')}  "
                f"zero-width {zero}  {row['median_seconds']:.1f} s/fit")
    return rows


def crosscheck(n):
    """Largest difference between reference and kernel tables, over the stated errors."""
    worst = 0.0
    for k in range(n):
        ref, ker = make_table("inside", k, "reference"), make_table("inside", k, "kernel")
        for col in ("exit_speed", "scattering_angle", "spin_out"):
            worst = max(worst, float(np.max(np.abs(ref[col] - ker[col]) / ref[f"{col}_err"])))
    print(f"{n} tables of 60 rows: reference and kernel differ by at most {worst:.2e} of a "
          f"stated error")
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=400)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--settings", default="inside,edges")
    parser.add_argument("--solver", choices=("kernel", "reference"), default="kernel")
    parser.add_argument("--out", default="fit-validation")
    parser.add_argument("--summary", metavar="DIR", help="only summarise DIR")
    parser.add_argument("--crosscheck", type=int, metavar="N",
                        help="compare N tables made by the reference and by the kernel")
    args = parser.parse_args()
    if args.crosscheck:
        crosscheck(args.crosscheck)
        return
    if args.summary:
        summary(args.summary)
        return
    settings = args.settings.split(",")
    unknown = [s for s in settings if s not in SETTINGS]
    if unknown:
        parser.error(f"unknown setting {unknown[0]!r} (choose from {', '.join(SETTINGS)})")
    Path(args.out).mkdir(parents=True, exist_ok=True)
    jobs = [(i, args.workers, args.tables, settings, args.out, args.solver)
            for i in range(args.workers)]
    if args.workers == 1:
        worker(jobs[0])
    else:
        with multiprocessing.get_context("spawn").Pool(args.workers) as pool:
            pool.map(worker, jobs)
    summary(args.out)


if __name__ == "__main__":
    sys.exit(main())
