"""``python -m validation pitch_movement``: the residual of the study's launch angle and
speed against the pitch's movement, per export and combined."""

import numpy as np
import pandas as pd
import pytest


def _table(n=3000, seed=5, rise=6.0, towards=-3.0):
    rng = np.random.default_rng(seed)
    hand = rng.choice(["R", "L"], n)
    side = np.where(hand == "L", -1.0, 1.0)
    pfx_x, pfx_z = rng.normal(0.0, 0.8, n), rng.normal(0.8, 0.6, n)
    spin = rng.normal(2300.0, 300.0, n)
    angle = rise * pfx_z + towards * (-pfx_x * side) + rng.normal(0.0, 20.0, n)
    return pd.DataFrame({"handedness": hand, "pfx_x": pfx_x, "pfx_z": pfx_z,
                         "release_spin_rate": spin, "launch_angle_residual": angle})


def test_coefficients_recover_the_rise_and_the_break_towards_the_batter():
    from validation.pitch_movement import coefficients

    beta, err = coefficients(_table(), "launch_angle_residual")
    assert abs(beta[0] - 6.0) < 3 * err[0] and err[0] < 1.0
    # a break towards either batter counts alike: the side flips pfx_x's sign
    assert abs(beta[1] + 3.0) < 3 * err[1] and err[1] < 1.0
    assert abs(beta[2]) < 3 * err[2]
    # without the batter's side the break would average out to nothing
    flipped = _table()
    flipped["handedness"] = "R"
    wrong, _ = coefficients(flipped, "launch_angle_residual")
    assert abs(wrong[1]) < abs(beta[1]) / 2


def test_combined_weights_each_estimate_by_its_error():
    from validation.pitch_movement import combined

    beta, err = combined([(np.array([1.0, 0.0]), np.array([1.0, 1.0])),
                          (np.array([4.0, 2.0]), np.array([2.0, 1.0]))])
    assert beta[0] == pytest.approx((1.0 + 4.0 / 4) / (1.0 + 1 / 4))
    assert beta[1] == pytest.approx(1.0)
    assert err[1] == pytest.approx(1 / np.sqrt(2))
