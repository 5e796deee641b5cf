"""Injection check of `mcbat fit --population`: tables simulated at known distribution
parameters, fitted back; prints the pulls and the MINOS intervals' coverage.

    NUMBA_NUM_THREADS=1 nice -n 15 .venv/bin/python -m validation population_injection \\
        --tables 200 --rows 500          # the full check (hours on 2 cores)
    ... --tables 20 --rows 200 --draws 40   # a reduced one

Each table: ``--rows`` batted balls of ``examples/population_game.toml`` with the truth
below, every ball meeting a real pitch of data/statcast_2020-09-03.csv (resampled). The
pull of a parameter is ``(fit - truth) / sigma`` with sigma the MINOS error on the truth's
side; coverage is the fraction of tables whose MINOS interval holds the truth (68.3 %
expected).
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np

import mcbat
from mcbat.statcast import read
from mcbat.stats.population import fit_population, population_table, simulate_table

ROOT = Path(__file__).resolve().parents[1]
TRUTH = {"swing.bat_speed.mean": 69.0, "swing.bat_speed.std": 6.0,
         "swing.attack_angle.mean": 12.0, "swing.attack_angle.std": 7.0,
         "contact.undercut.std": 0.9}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tables", type=int, default=20)
    ap.add_argument("--rows", type=int, default=200)
    ap.add_argument("--draws", type=int, default=None, help="template draws per row")
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--out", default=None, help="write every table's fit as JSON lines")
    ap.add_argument("--combine", nargs="+", default=None, metavar="FIT.jsonl",
                    help="only summarise the fits of earlier runs' --out files")
    args = ap.parse_args(argv)
    if args.combine:
        fits = [json.loads(line) for name in args.combine for line in open(name)]
        summarise(fits, len(fits), fits[0]["rows"] if fits else 0, [])
        return
    study = mcbat.load_study(ROOT / "examples" / "population_game.toml")
    pitches, _ = population_table(read(ROOT / "data" / "statcast_2020-09-03.csv"))
    fits, seconds = [], []
    sink = open(args.out, "w") if args.out else None
    for k in range(args.tables):
        table = simulate_table(study, pitches, args.rows, seed=args.seed + k, values=TRUTH)
        t0 = time.process_time()
        result = fit_population(study, table, list(TRUTH), draws=args.draws,
                                seed=args.seed + k)
        seconds.append(time.process_time() - t0)
        fits.append(result.to_dict())
        if sink:
            sink.write(json.dumps(fits[-1]) + "\n")
            sink.flush()
        print(f"table {k + 1}/{args.tables}: {seconds[-1]:.1f} s CPU, "
              f"p = {result.p_value:.3f}", flush=True)
    summarise(fits, args.tables, args.rows, seconds)


def summarise(fits, tables, rows, seconds):
    """Print the pulls, coverage and p-values of ``fits`` (``to_dict`` of each)."""
    pulls = {name: [] for name in TRUTH}
    covered = {name: [] for name in TRUTH}
    missing = {name: 0 for name in TRUTH}
    for fit in fits:
        for p in fit["parameters"]:
            truth = TRUTH[p["name"]]
            sigma = p["upper_error"] if truth > p["value"] else p["lower_error"]
            if not sigma:
                missing[p["name"]] += 1
                continue
            pulls[p["name"]].append((p["value"] - truth) / sigma)
            covered[p["name"]].append(abs(p["value"] - truth) <= sigma)
    cpu = f", median fit {np.median(seconds):.1f} s CPU" if seconds else ""
    print(f"\n{tables} tables of {rows} rows{cpu}")
    print(f"{'parameter':32s} {'mean pull':>10s} {'pull sd':>8s} {'coverage':>9s} {'n':>4s} "
          f"{'no interval':>11s}")
    for name in TRUTH:
        x = np.array(pulls[name])
        se = x.std(ddof=1) / np.sqrt(len(x)) if len(x) > 1 else float("nan")
        print(f"{name:32s} {x.mean():+10.3f} {x.std(ddof=1):8.3f} "
              f"{100 * np.mean(covered[name]):8.1f}% {len(x):4d} {missing[name]:11d}"
              f"   (mean's se {se:.3f})")
    p = np.array([fit["p_value"] for fit in fits])
    print(f"goodness of fit: p-values' mean {p.mean():.3f} (0.5 expected), "
          f"{100 * np.mean(p < 0.05):.1f} % below 0.05")


if __name__ == "__main__":
    main()
