"""Injection test of the flight calibration (``mcbat fit --flight``): synthetic distances
from known drag and lift scales, refitted; how often the 68 % profile-likelihood interval
holds the truth.

The launches are the real ones of the calibration sample (the outfield catches and home
runs of the shipped Statcast samples, flown with Nathan's average spin at their parks'
elevations and catch heights). Each table's distances are the model's at the true scales
plus normal scatter of ``--sigma`` ft; each table is fitted as a real one is
(:func:`mcbat.papers.statcast.calibrate.fit_scales`: the scatter estimated from the
residuals, then the profile intervals).

    .venv/bin/python -m validation flight_calibration_coverage --tables 200

One kernel thread by default (``--threads``): a fit flies ~130 balls at a time, too few to
gain from threads on a busy machine.

Prints the coverage of each parameter with its binomial standard error, and the mean and
standard deviation of the pulls ``(fit - truth) / error``.
"""

from __future__ import annotations

import argparse
import math
import time

import numba
import numpy as np

from mcbat.papers.statcast.calibrate import FIT_CLASSES, fit_scales, flight_table, predict
from mcbat.papers.statcast.compare import select_balls
from mcbat.papers.statcast.reproduce import read_statcast
from mcbat.statcast.spin import nathan_average_spin
from mcbat.stats.models.flight import FlightFitSetup


def sample_table(rows=None, seed=0):
    """The calibration sample's launches as a flight table (distances still measured);
    ``rows``: a random subset of that many balls."""
    table, _ = read_statcast()
    balls = select_balls(table)
    balls = balls[balls["comparison"].isin(FIT_CLASSES)].reset_index(drop=True)
    backspin, sidespin = nathan_average_spin(balls["launch_angle"], balls["spray_angle"],
                                             balls["handedness"])
    flights = flight_table(balls, backspin, sidespin, 1.0)
    setup = FlightFitSetup()
    flights = flights[np.isfinite(predict(setup, flights))].reset_index(drop=True)
    if rows is not None:
        pick = np.random.default_rng(seed).choice(len(flights), rows, replace=False)
        flights = flights.iloc[np.sort(pick)].reset_index(drop=True)
    return flights


def inject(flights, truth, sigma, rng):
    """A copy of ``flights`` with distances drawn at the true scales."""
    table = flights.copy()
    exact = predict(FlightFitSetup(), table, truth)
    table["hit_distance_sc"] = exact + sigma * rng.standard_normal(len(table))
    return table


def coverage(tables, truth, sigma, seed=0, rows=None, intervals="profile", echo=print):
    """Fit ``tables`` injected tables; returns per parameter the fraction of intervals
    holding the truth and the pulls."""
    flights = sample_table(rows, seed)
    rng = np.random.default_rng(seed)
    hits = {p: 0 for p in truth}
    pulls = {p: [] for p in truth}
    for k in range(tables):
        cal = fit_scales(inject(flights, truth, sigma, rng), intervals=intervals)
        for p, true in truth.items():
            value = cal.result.params[p]
            iv = cal.result.intervals.get(p, {})
            lo = iv.get("lower_error") or cal.result.stderr[p]
            hi = iv.get("upper_error") or cal.result.stderr[p]
            hits[p] += value - lo <= true <= value + hi
            pulls[p].append((value - true) / (hi if value < true else lo))
        if echo and (k + 1) % 20 == 0:
            echo(f"  {k + 1} tables: " + ", ".join(
                f"{p} {hits[p] / (k + 1):.3f}" for p in truth))
    return {p: hits[p] / tables for p in truth}, {p: np.array(v) for p, v in pulls.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tables", type=int, default=200)
    parser.add_argument("--drag", type=float, default=0.9, help="true drag_scale")
    parser.add_argument("--lift", type=float, default=1.2, help="true lift_scale")
    parser.add_argument("--sigma", type=float, default=15.0, help="scatter per ball, ft")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args(argv)
    numba.set_num_threads(args.threads)
    truth = {"drag_scale": args.drag, "lift_scale": args.lift}
    t0 = time.perf_counter()
    cover, pulls = coverage(args.tables, truth, args.sigma, args.seed)
    n = args.tables
    print(f"{n} tables of {len(sample_table())} balls, truth {truth}, sigma {args.sigma} ft, "
          f"seed {args.seed} ({time.perf_counter() - t0:.0f} s)")
    for p in truth:
        se = math.sqrt(0.683 * 0.317 / n)
        print(f"  {p}: coverage {cover[p]:.3f} (68.3 % expected, binomial se {se:.3f}); "
              f"pulls mean {pulls[p].mean():+.3f}, sd {pulls[p].std(ddof=1):.3f}")


if __name__ == "__main__":
    main()
