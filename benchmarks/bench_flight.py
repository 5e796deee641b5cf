"""Speed of the flight: the batch kernel alone, and a game study with flight through
`mcbat run`.

Run:  .venv/bin/python -m benchmarks flight [--n N] [--repeats K] [--runs R]
                                                   [--run-samples S]

1. ``fly_batch`` on N random launches (60-120 mph, -10..60 deg, spray +-45 deg, 0-4000 rpm
   of backspin and +-2000 rpm of sidespin), default settings, all numba threads: flights/s
   (median of K).
2. ``mcbat run studies/game_fastball.toml`` (which has a [flight] section), S samples:
   rows/s as the run reports it (median of R runs).
"""

import argparse
import math
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numba
import numpy as np

import harness
from mcbat.core.flight.trajectory import allocate_flight_outputs, fly_batch, pack_params
from mcbat.solving.derived import launch_vectors
from mcbat.study.flight import FlightSettings

ROOT = Path(__file__).resolve().parents[1]
MPH, DEG, RPM = 0.44704, math.pi / 180, 2 * math.pi / 60
#: python -m benchmarks --quick flight
QUICK_ARGS = ["--n", "100000", "--repeats", "3", "--runs", "0"]


def launches(n, seed=1):
    rng = np.random.default_rng(seed)
    v, w = launch_vectors(rng.uniform(60, 120, n) * MPH, rng.uniform(-10, 60, n) * DEG,
                          rng.uniform(-45, 45, n) * DEG, rng.uniform(0, 4000, n) * RPM,
                          rng.uniform(-2000, 2000, n) * RPM, np.zeros(n))
    return np.stack(v), np.stack(w)


def kernel(n, repeats):
    settings = FlightSettings()
    v, w = launches(n)
    start = np.repeat(np.asarray(settings.start)[:, None], n, axis=1)
    params = pack_params(settings.params(0.145, 0.036))
    out, status = allocate_flight_outputs(n)
    timing = harness.median_time(lambda: fly_batch(params, start, v, w, out, status), repeats)
    rate = n / timing.median
    print(f"flight kernel: {rate:,.0f} flights/s ({numba.get_num_threads()} threads, {n:,} "
          f"launches, median of {repeats}; mean {out[5].mean():.2f} steps, "
          f"{(status == 0).mean():.0%} ok)")
    return rate, float(out[5].mean()), float((status == 0).mean())


def runs(n, count):
    work = Path(tempfile.mkdtemp(prefix="mcbat-bench-flight-"))
    rates = []
    try:
        for _ in range(count):
            shutil.rmtree(work / "d", ignore_errors=True)
            proc = subprocess.run([sys.executable, "-m", "mcbat.cli", "run",
                                   str(ROOT / "studies" / "game_fastball.toml"), "--samples",
                                   str(n), "--out", str(work / "d"), "--quiet"],
                                  capture_output=True, text=True, check=True)
            found = re.search(r"\(([\d,]+) rows/s\)", proc.stdout)
            rates.append(float(found.group(1).replace(",", "")))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    rate = statistics.median(rates)
    print(f"mcbat run game_fastball with [flight]: {rate:,.0f} rows/s ({n:,} samples, "
          f"median of {count}: {', '.join(f'{r:,.0f}' for r in rates)})")
    return rate


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--run-samples", type=int, default=400_000,
                        help="samples of each mcbat run (default 400,000)")
    args = parser.parse_args(argv)
    rate, steps, ok = kernel(args.n, args.repeats)
    metrics = {"flights_per_s": rate, "steps_mean": steps, "ok_fraction": ok}
    if args.runs:
        metrics["game_run_rows_per_s"] = runs(args.run_samples, args.runs)
    harness.record("flight", metrics, {
        "launches": args.n, "repeats": args.repeats, "threads": numba.get_num_threads(),
        "runs": args.runs, "run_samples": args.run_samples if args.runs else None,
        "launch_ranges": "60-120 mph, -10..60 deg, 0-4000 rpm backspin, seed 1"})


if __name__ == "__main__":
    main()
