"""Time of a population fit: 500 rows, 5 free parameters (median of 3 runs).

    NUMBA_NUM_THREADS=2 nice -n 15 .venv/bin/python -m benchmarks population_timing

The table is simulated once (not timed) from examples/population_game.toml on the real
pitches of data/statcast_2020-09-03.csv; each run fits it from scratch (template draws,
two proposal passes, MIGRAD, HESSE, MINOS) with the default draws: the five free
parameters and three observables of the injection check's ``spread`` set. Wall and CPU time
are printed: on a shared machine the CPU time is the one that measures the fit.
"""

import argparse
import time
from pathlib import Path

import numba
import numpy as np

import harness
import mcbat
from harness.population import SETS, TRUTH
from mcbat.statcast import read
from mcbat.stats.population.fit import fit_population, population_table, simulate_table

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rows", type=int, default=500)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--engine", default="memory")
    args = ap.parse_args(argv)
    study = mcbat.load_study(ROOT / "examples" / "population_game.toml")
    pitches, _ = population_table(read(ROOT / "data" / "statcast_2020-09-03.csv"))
    free, observables = SETS["spread"]
    truth = {name: TRUTH[name] for name in free}
    table = simulate_table(study, pitches, args.rows, seed=42, values=truth)
    fit_population(study, table.iloc[:50], ["swing.bat_speed.mean"], draws=20, passes=1)
    times, cpu = [], []
    for _ in range(args.repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        result = fit_population(study, table, list(free), observables=observables,
                                engine=args.engine)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        print(f"  {times[-1]:.1f} s wall, {cpu[-1]:.1f} s CPU", flush=True)
    print(f"population fit, {result.rows} rows, {len(free)} free, {result.draws:,} draws, "
          f"engine {args.engine}, {numba.get_num_threads()} threads: median "
          f"{np.median(times):.1f} s wall of {args.repeats} "
          f"({', '.join(f'{t:.1f}' for t in times)}); CPU median {np.median(cpu):.1f} s "
          f"(the wall time on a machine shared with other work overstates it)")
    harness.record("population_timing", {
        "wall_s": float(np.median(times)), "cpu_s": float(np.median(cpu)),
        "times_s": times, "draws": result.draws},
        {"rows": args.rows, "repeats": args.repeats, "engine": args.engine,
         "free": list(free), "observables": list(observables), "threads": numba.get_num_threads()})


if __name__ == "__main__":
    main()
