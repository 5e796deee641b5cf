"""Throughput of the spin inference: read a tidy Statcast table from Parquet, infer every
ball's contact and spin, and (``--fly``) fly every inferred ball to the ground.

The balls are simulated with the game kernel from known contacts (the forward model,
``mcbat.inference.predict_batted_balls``) on sampled pitches and swings like the game
presets', written with ``mcbat.statcast.write`` and timed through ``mcbat.statcast.read``
+ ``mcbat.inference.infer_spin``. Each run is one read and one inference of all balls;
the median over runs is reported (the first, compiling run is left out).

    .venv/bin/python -m benchmarks inference --n 100000 --runs 5
    .venv/bin/python -m benchmarks inference --n 100000 --runs 5 --bat-speed
    .venv/bin/python -m benchmarks inference --n 100000 --runs 5 --fly
"""

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
import pandas as pd

import harness
from mcbat import statcast
from mcbat.bodies.presets import BALL_PRESETS
from mcbat.inference import infer_spin, predict_batted_balls
from mcbat.study.flight import FlightSettings, fly_launches

MPH, DEG, RPM = 0.44704, np.pi / 180, np.pi / 30

#: python -m benchmarks --quick inference
QUICK_ARGS = ["--n", "5000", "--runs", "3"]


def fly(df, spin):
    """Every inferred ball flown with the published flight model (standard conditions)."""
    ok = spin["inferred"].to_numpy(bool)
    ball = BALL_PRESETS["baseball"]
    out, status = fly_launches(
        FlightSettings(), ball.mass, ball.radius, df["launch_speed"].to_numpy()[ok] * MPH,
        df["launch_angle"].to_numpy()[ok] * DEG, df["spray_angle"].to_numpy()[ok] * DEG,
        spin["backspin"].to_numpy()[ok] * RPM, spin["sidespin"].to_numpy()[ok] * RPM,
        spin["gyrospin"].to_numpy()[ok] * RPM)
    return int((status == 0).sum())


def simulate(n, seed, with_bat_speed):
    rng = np.random.default_rng(seed)
    hand = np.where(rng.random(n) < 0.6, "R", "L")
    table = pd.DataFrame({
        "pitch_speed": rng.normal(86, 6, n).clip(70, 100),
        "vertical_approach_angle": rng.normal(-6.5, 1.5, n).clip(-12, -2),
        "horizontal_approach_angle": rng.normal(0, 1.5, n).clip(-5, 5),
        "spin_rate": rng.normal(2250, 300, n).clip(1200, 3200),
        "spin_axis": rng.uniform(0, 360, n), "handedness": hand,
    })
    bat_speed = rng.normal(71.5, 4, n).clip(60, 82)
    if with_bat_speed:
        table["bat_speed"] = bat_speed
        table["attack_angle"] = rng.normal(10, 5, n).clip(-10, 30)
    z = rng.uniform(0.15, 0.24, n) if with_bat_speed else None
    balls = predict_batted_balls(table, undercut=rng.uniform(-0.025, 0.025, n),
                                 attack_direction=rng.normal(0, 8, n).clip(-30, 30),
                                 bat_speed=bat_speed, from_barrel_end=z)
    ok = (balls["status"] == "ok").to_numpy()
    table = table.assign(launch_speed=balls["launch_speed"], launch_angle=balls["launch_angle"],
                         spray_angle=balls["spray_angle"])[ok].reset_index(drop=True)
    tidy = pd.DataFrame({name: np.full(len(table), np.nan) for name in statcast.COLUMNS})
    for name in ("pitch_type", "p_throws", "description", "events", "bb_type", "home_team",
                 "game_date"):
        tidy[name] = None
    tidy["description"] = "hit_into_play"
    for name in table.columns:
        tidy[name] = table[name].to_numpy()
    return tidy


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--fly", action="store_true",
                        help="also fly every inferred ball (read + infer + fly)")
    parser.add_argument("--bat-speed", action="store_true",
                        help="measured bat speed and attack angle (the contact position is "
                             "inferred)")
    args = parser.parse_args(argv)
    tidy = simulate(args.n, args.seed, args.bat_speed)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "balls.parquet"
        statcast.write(tidy, path)
        head = statcast.read(path).head(64)
        warm = infer_spin(head)  # compile (or load the cache)
        if args.fly:
            fly(head, warm)
        rates, cpu_rates, out, flown = [], [], None, None
        for _ in range(args.runs):
            t0, c0 = time.perf_counter(), time.process_time()
            df = statcast.read(path)
            out = infer_spin(df)
            if args.fly:
                flown = fly(df, out)
            rates.append(len(df) / (time.perf_counter() - t0))
            cpu_rates.append(len(df) / (time.process_time() - c0))
    it = out["inference_iterations"]
    mode = "bat speed measured" if args.bat_speed else "bat speed inferred"
    print(f"balls: {len(tidy)} ({mode}), threads: {numba.get_num_threads()}")
    print(f"status: {out.attrs['status_counts']}")
    print(f"Newton iterations: median {it.median():.0f}, mean {it.mean():.2f}, "
          f"max {it.max()}; game-kernel calls per ball: mean "
          f"{out['kernel_evaluations'].mean():.2f}")
    stages = "read + infer + fly" if args.fly else "read + infer"
    if args.fly:
        print(f"flown to the ground: {flown} balls")
    print(f"{stages}, balls/s per run: " + ", ".join(f"{r:,.0f}" for r in rates))
    print(f"median: {statistics.median(rates):,.0f} balls/s")
    # On a shared machine the wall-clock rate depends on the other jobs; the CPU time the
    # process used does not (much): balls per CPU-second, and that times the threads.
    cpu = statistics.median(cpu_rates)
    print(f"CPU time: median {cpu:,.0f} balls per CPU-second "
          f"(x {numba.get_num_threads()} threads = {cpu * numba.get_num_threads():,.0f} "
          "balls/s on as many idle cores)")
    harness.record("inference", {
        "balls_per_s": statistics.median(rates), "runs_balls_per_s": rates,
        "balls_per_cpu_s": cpu, "iterations_mean": float(it.mean()),
        "status_counts": {str(k): int(v) for k, v in out.attrs["status_counts"].items()}},
        {"balls": args.n, "runs": args.runs, "seed": args.seed, "fly": args.fly,
         "bat_speed_measured": args.bat_speed, "threads": numba.get_num_threads()})


if __name__ == "__main__":
    main()
