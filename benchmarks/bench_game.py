"""Cost of the game layer: the same impacts through the game kernel and the bat-frame kernel.

Draws N rows of ``studies/game_fastball.toml``, solves them once with the game kernel to
get their bat-frame cases, then times, interleaved, ``solve_game_batch`` on the game
inputs and ``solve_batch`` on the very same impacts in the bat frame. Prints the medians
and the ratio (the transform's overhead).

    .venv/bin/python benchmarks/bench_game.py [N] [REPEATS]
"""

import statistics
import sys
import time
from pathlib import Path

import numba
import numpy as np

from mcbat.core.batch import INPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.swing import (
    GAME_INPUT_FIELDS,
    allocate_game_outputs,
    bat_frame_columns,
    solve_game_batch,
)
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[1]


def main(n=400_000, repeats=7):
    study = load_study(ROOT / "studies" / "game_fastball.toml")
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
    g, b = statistics.median(t_game), statistics.median(t_bat)
    print(f"{n:,} rows of game_fastball, {numba.get_num_threads()} threads, "
          f"{repeats} interleaved repeats (medians)")
    print(f"  game kernel:      {n / g:,.0f} rows/s ({g:.3f} s)")
    print(f"  bat-frame kernel: {n / b:,.0f} rows/s ({b:.3f} s), same impacts")
    print(f"  game / bat-frame time: {g / b:.3f} (transform overhead {100 * (g / b - 1):+.1f} %)")
    print(f"  outputs identical: {np.array_equal(out, out2, equal_nan=True)}")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
