"""The inferred backspin's slopes on the launch angle, against Nathan's average model of
tracked batted balls: like for like on the same balls."""

import numpy as np
import pandas as pd
import pytest

from mcbat.inference.compare import MIN_BALLS, NATHAN_SLOPE, backspin_slopes
from mcbat.statcast.spin import nathan_average_spin


def _balls(n, seed=0):
    rng = np.random.default_rng(seed)
    la = rng.uniform(0, 50, n)
    spray = rng.uniform(-40, 40, n) + 0.5 * la  # higher balls more often the other way
    hand = rng.choice(["R", "L"], n)
    return pd.DataFrame({"launch_angle": la, "spray_angle": spray, "handedness": hand})


def test_nathans_own_spin_gives_his_slopes():
    balls = _balls(400)
    backspin, _ = nathan_average_spin(balls.launch_angle, balls.spray_angle, balls.handedness)
    spin = pd.DataFrame({"backspin": backspin, "inference_status": "converged"})
    s = backspin_slopes(balls, spin)
    inside = (balls.launch_angle >= 10) & (balls.launch_angle <= 40)
    assert s.balls == int(inside.sum())
    assert s.inferred == pytest.approx(s.nathan_same_balls, rel=1e-9)
    assert s.inferred_spray_held == pytest.approx(NATHAN_SLOPE, rel=1e-9)
    # (the spray angle's drift with the launch angle moves the plain slope off 120)
    assert abs(s.nathan_same_balls - NATHAN_SLOPE) > 1.0


def test_a_spin_a_tenth_above_nathans_reads_a_tenth_above_and_failures_are_left_out():
    balls = _balls(400, seed=1)
    backspin, _ = nathan_average_spin(balls.launch_angle, balls.spray_angle, balls.handedness)
    status = np.where(np.arange(400) % 5 == 0, "no_solution", "converged")
    spin = pd.DataFrame({"backspin": np.where(status == "converged", 1.1 * backspin, 9e9),
                         "inference_status": status})
    s = backspin_slopes(balls, spin)
    assert s.inferred == pytest.approx(1.1 * s.nathan_same_balls, rel=1e-9)
    assert s.inferred_spray_held == pytest.approx(1.1 * NATHAN_SLOPE, rel=1e-9)


def test_too_few_balls_give_no_slope():
    balls = _balls(MIN_BALLS - 1)
    balls["launch_angle"] = 20.0
    spin = pd.DataFrame({"backspin": 1000.0, "inference_status": "converged"},
                        index=balls.index)
    assert backspin_slopes(balls, spin) is None


def test_mcbat_infer_prints_the_slopes(cli):
    done = cli("infer", "data/statcast_2020-09-03.csv")
    assert done.returncode == 0, done.stderr
    line = [x for x in done.stdout.splitlines() if "backspin rises" in x]
    assert len(line) == 1 and "Nathan's average model on the same balls" in line[0]
