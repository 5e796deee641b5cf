"""Cost of the game layer: kernel against kernel, and `mcbat run` against `mcbat run`.

1. Kernels. Draws N rows of ``studies/game_fastball.toml``, solves them once with the game
   kernel to get their bat-frame cases, then times, interleaved, ``solve_game_batch`` on
   the game inputs and ``solve_batch`` on the very same impacts in the bat frame (outputs
   checked identical). The difference is what the transform costs per row.
2. Runs (``--runs R``). Times ``mcbat run`` of ``game_fastball`` and of the bat-frame
   ``studies/throughput.toml`` (the same N samples, 2 threads, interleaved, R runs each,
   medians of the rows/s each run reports), and gives the transform's share of the game
   run: the kernel difference of part 1 over the game run's time per row.

    .venv/bin/python -m benchmarks game [--n N] [--repeats K] [--runs R]
"""

import argparse
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba
import numpy as np

import harness
from mcbat.core.batch import INPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.swing.game import (
    GAME_INPUT_FIELDS,
    allocate_game_outputs,
    bat_frame_columns,
    solve_game_batch,
)
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[1]
STUDIES = {"game_fastball": ROOT / "studies" / "game_fastball.toml",
           "throughput": ROOT / "studies" / "throughput.toml"}
#: python -m benchmarks --quick game
QUICK_ARGS = ["--n", "50000", "--repeats", "3"]


def kernels(n, repeats):
    """Seconds per row of the game kernel and of the bat-frame kernel (medians)."""
    study = load_study(STUDIES["game_fastball"])
    cols = study.sample(0, n)
    game = np.stack([cols[f] for f in GAME_INPUT_FIELDS])
    s = study.solver
    args = (s["steps"], s["tolerance"], s["max_steps"])
    frame, out, game_out, status, end_state = allocate_game_outputs(n)
    solve_game_batch(game, *args, frame, out, game_out, status, end_state)  # warm
    columns = bat_frame_columns(game, frame)
    bat = np.stack([columns[name] for name in INPUT_FIELDS])
    out2, status2, end2 = allocate_outputs(n)
    solve_batch(bat, *args, out2, status2, end2)
    assert np.array_equal(out, out2, equal_nan=True), "the two kernels disagree"
    t_game, t_bat = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        solve_game_batch(game, *args, frame, out, game_out, status, end_state)
        t_game.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        solve_batch(bat, *args, out2, status2, end2)
        t_bat.append(time.perf_counter() - t0)
    g, b = statistics.median(t_game) / n, statistics.median(t_bat) / n
    print(f"kernels: {n:,} rows of game_fastball, {numba.get_num_threads()} threads, "
          f"{repeats} interleaved repeats (medians)")
    print(f"  game kernel:      {1 / g:,.0f} rows/s")
    print(f"  bat-frame kernel: {1 / b:,.0f} rows/s, same impacts, outputs identical")
    print(f"  game / bat-frame time: {g / b:.3f} (transform +{1e9 * (g - b):.0f} ns per row, "
          f"{100 * (g / b - 1):+.1f} % of the kernel)")
    return g, b


def runs(n, count):
    """Median rows/s of ``mcbat run`` for each study (interleaved)."""
    work = Path(tempfile.mkdtemp(prefix="mcbat-bench-game-"))
    rates = {name: [] for name in STUDIES}
    try:
        for _ in range(count):
            for name, path in STUDIES.items():
                shutil.rmtree(work / name, ignore_errors=True)  # else it resumes
                proc = subprocess.run(
                    [sys.executable, "-m", "mcbat.cli", "run", str(path), "--samples", str(n),
                     "--out", str(work / name), "--threads", "2"],
                    capture_output=True, text=True, check=True)
                found = re.search(r"\(([\d,]+) rows/s\)", proc.stdout)
                if found is None:
                    raise RuntimeError(f"no rows/s in the output of {name}:\n{proc.stdout}")
                rates[name].append(float(found.group(1).replace(",", "")))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return {name: statistics.median(r) for name, r in rates.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--runs", type=int, default=0)
    args = parser.parse_args(argv)
    g, b = kernels(args.n, args.repeats)
    metrics = {"game_kernel_rows_per_s": 1 / g, "bat_frame_kernel_rows_per_s": 1 / b,
               "transform_ns_per_row": 1e9 * (g - b), "transform_fraction": g / b - 1}
    if args.runs:
        rates = runs(args.n, args.runs)
        print(f"mcbat run, {args.n:,} samples, 2 threads, {args.runs} interleaved runs "
              "(medians of the rows/s each run reports):")
        for name, rate in rates.items():
            print(f"  {name}: {rate:,.0f} rows/s")
        share = (g - b) * rates["game_fastball"]
        print(f"  the transform's share of the game run: {100 * share:.1f} % "
              f"({1e9 * (g - b):.0f} ns of {1e9 / rates['game_fastball']:.0f} ns per row)")
        metrics.update(run_rows_per_s=rates, transform_share_of_run=share)
    harness.record("game", metrics, {"rows": args.n, "repeats": args.repeats,
                                     "threads": numba.get_num_threads(), "runs": args.runs,
                                     "study": "studies/game_fastball.toml"})


if __name__ == "__main__":
    main()
