"""Injection check of `mcbat fit --population`: tables simulated at known distribution
parameters, fitted back; prints the pulls and the MINOS intervals' coverage.

    NUMBA_NUM_THREADS=1 nice -n 15 .venv/bin/python -m validation population_injection \\
        --tables 200 --rows 500 --out fits500.jsonl      # the full check, per table size
    ... --tables 20 --rows 200 --draws 40                # a reduced one
    ... --rows 500 --combine fits500.jsonl               # summarise earlier runs

Each table: ``--rows`` batted balls of ``examples/population_game.toml`` with the truth of
``harness.population.TRUTH`` (shared with ``python -m benchmarks population_timing``), every
ball meeting a real pitch of data/statcast_2020-09-03.csv (resampled). The
pull of a parameter is ``(fit - truth) / sigma`` with sigma the MINOS error on the truth's
side; coverage is the fraction of tables whose MINOS interval holds the truth (68.3 %
expected).

Two parameter sets (``--set``), five free parameters each:

* ``spread`` (default): the bat speed's mean and width, the attack angle's mean, the
  undercut's width and the width of the swing's direction, fitted to launch speed, launch
  angle and spray angle: each parameter leaves its own mark on the observables.
* ``widths``: the same but the attack angle's width in place of the swing direction's,
  fitted to launch speed and angle alone. Both widths spread the launch angle, and below a
  few hundred rows the data cannot tell them apart (one ends at its limit, the other
  stands in for it): the set shows what a fit of two such widths does to small tables.

With ``--out`` every fit is appended as a JSON line and a rerun with the same file goes on
after the tables already there, so a long check can be interrupted.
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np

import harness
import mcbat
from harness.population import SETS, TRUTH
from mcbat.statcast import read
from mcbat.stats.population.fit import fit_population, population_table, simulate_table

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tables", type=int, default=20)
    ap.add_argument("--rows", type=int, default=200)
    ap.add_argument("--draws", type=int, default=None, help="template draws per row")
    ap.add_argument("--bins", type=int, default=None,
                    help="bins per observable (default: the fit's own choice)")
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--set", choices=sorted(SETS), default="spread",
                    help="the free parameters and observables (see the module's docstring)")
    ap.add_argument("--out", default=None, help="write every table's fit as JSON lines")
    ap.add_argument("--combine", nargs="+", default=None, metavar="FIT.jsonl",
                    help="only summarise the fits of earlier runs' --out files")
    args = ap.parse_args(argv)
    if args.combine:
        fits = [json.loads(line) for name in args.combine for line in open(name)]
        summarise(fits, len(fits), args.rows, [])
        return
    free, observables = SETS[args.set]
    truth = {name: TRUTH[name] for name in free}
    study = mcbat.load_study(ROOT / "examples" / "population_game.toml")
    pitches, _ = population_table(read(ROOT / "data" / "statcast_2020-09-03.csv"))
    fits, seconds = [], []
    if args.out and Path(args.out).exists():
        fits = [json.loads(line) for line in open(args.out)]
    sink = open(args.out, "a") if args.out else None
    for k in range(len(fits), args.tables):
        table = simulate_table(study, pitches, args.rows, seed=args.seed + k, values=truth)
        t0 = time.process_time()
        result = fit_population(study, table, list(truth), observables=observables,
                                draws=args.draws, bins=args.bins, seed=args.seed + k)
        seconds.append(time.process_time() - t0)
        fits.append(result.to_dict() | {"table": k, "seed": args.seed + k,
                                        "truth": truth, "set": args.set})
        if sink:
            sink.write(json.dumps(fits[-1]) + "\n")
            sink.flush()
        print(f"table {k + 1}/{args.tables}: {seconds[-1]:.1f} s CPU, "
              f"p = {result.p_value:.3f}", flush=True)
    summarise(fits, args.tables, args.rows, seconds)


def holds(pulls, covered):
    """The check's criterion: mean pull within +-0.2, pull sd 0.8-1.2, coverage 68 +- 5 %."""
    return (len(pulls) > 1 and abs(np.mean(pulls)) <= 0.2
            and 0.8 <= np.std(pulls, ddof=1) <= 1.2 and abs(np.mean(covered) - 0.683) <= 0.05)


def summarise(fits, tables, rows, seconds):
    """Print the pulls, coverage and p-values of ``fits`` (``to_dict`` of each); with the
    run's ``--results DIR``, record them as ``population_injection_<rows>``."""
    names = list(fits[0]["truth"]) if fits else []
    pulls = {name: [] for name in names}
    covered = {name: [] for name in names}
    missing = {name: 0 for name in names}
    for fit in fits:
        for p in fit["parameters"]:
            truth = fit["truth"][p["name"]]
            sigma = p["upper_error"] if truth > p["value"] else p["lower_error"]
            if not sigma:
                # no interval: counted against the coverage, left out of the pulls
                missing[p["name"]] += 1
                covered[p["name"]].append(False)
                continue
            pulls[p["name"]].append((p["value"] - truth) / sigma)
            covered[p["name"]].append(abs(p["value"] - truth) <= sigma)
    cpu = f", median fit {np.median(seconds):.1f} s CPU" if seconds else ""
    print(f"\n{tables} tables of {rows} rows{cpu}")
    print("criterion: mean pull within +-0.2, pull sd 0.8-1.2, coverage 68 +- 5 % "
          "(a table without an interval counts as not covering)")
    print(f"{'parameter':32s} {'mean pull':>10s} {'pull sd':>8s} {'coverage':>9s} {'n':>4s} "
          f"{'no interval':>11s}")
    table = {}
    for name in names:
        x = np.array(pulls[name])
        se = x.std(ddof=1) / np.sqrt(len(x)) if len(x) > 1 else float("nan")
        ok = bool(holds(x, covered[name]))
        table[name] = {"truth": fits[0]["truth"][name], "mean_pull": float(x.mean()),
                       "mean_pull_se": float(se), "pull_sd": float(x.std(ddof=1)),
                       "coverage": float(np.mean(covered[name])), "pulls": len(x),
                       "no_interval": missing[name], "holds": ok}
        print(f"{name:32s} {x.mean():+10.3f} {x.std(ddof=1):8.3f} "
              f"{100 * np.mean(covered[name]):8.1f}% {len(x):4d} {missing[name]:11d}"
              f"   (mean's se {se:.3f}){'' if ok else '  FAILS'}")
    p = np.array([fit["p_value"] for fit in fits])
    print(f"goodness of fit: p-values' mean {p.mean():.3f} (0.5 expected), "
          f"{100 * np.mean(p < 0.05):.1f} % below 0.05")
    if fits:
        harness.record(f"population_injection_{rows}", {
            "parameters": table, "p_value_mean": float(p.mean()),
            "p_below_005": float(np.mean(p < 0.05))},
            {"tables": len(fits), "rows": rows, "set": fits[0].get("set"),
             "observables": fits[0]["observables"],
             "seeds": sorted({fit.get("seed") for fit in fits if "seed" in fit})[:1]
             + sorted({fit.get("seed") for fit in fits if "seed" in fit})[-1:],
             "draws_per_row": fits[0]["draws"] // max(fits[0]["rows"], 1)})


if __name__ == "__main__":
    main()
