"""Measured swings in infer_spin: unusable swings get their own status, and a measured bat
speed is moved within its error only where no contact position gives the ball."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mcbat.statcast as sc
from mcbat.inference import InferenceOptions, infer_spin

SHARED = Path(__file__).parents[2] / ".." / "shared" / "data" / "statcast"


def _balls():
    return pd.DataFrame({
        "pitch_speed": [86.0] * 4, "vertical_approach_angle": [-5.0] * 4,
        "horizontal_approach_angle": [0.0] * 4, "spin_rate": [2300.0] * 4,
        "spin_axis": [210.0] * 4, "handedness": ["R"] * 4,
        "launch_speed": [95.0, 95.0, 30.0, 95.0], "launch_angle": [15.0, 15.0, -20.0, 15.0],
        "spray_angle": [-5.0] * 4,
        "bat_speed": [72.0, 72.0, 8.0, 72.0], "attack_angle": [8.0, 8.0, 1.0, 8.0],
        "attack_direction": [2.0, -175.8, 5.0, 2.0],
        "description": ["hit_into_play"] * 3 + ["hit_into_play"],
        "events": ["single", "field_out", "single", "sac_bunt"]})


def test_out_of_range_swings_do_not_refuse_the_table():
    out = infer_spin(_balls())
    status = list(out["inference_status"].astype(str))
    assert status == ["converged", "unusable_swing", "unusable_swing", "unusable_swing"]
    assert out.attrs["status_counts"]["unusable_swing"] == 3
    assert out.attrs["unusable_swing"]["bunt"] == 2  # -175.8 deg, and the sac bunt
    assert out.attrs["unusable_swing"]["below_floor"] == 1
    assert out.loc[1:, "backspin"].isna().all()


def test_required_columns_keep_their_errors():
    balls = _balls()
    balls.loc[0, "launch_angle"] = 95.0
    from mcbat.errors import InputError

    with pytest.raises(InputError, match="launch_angle"):
        infer_spin(balls)


@pytest.fixture(scope="module")
def ohtani():
    path = SHARED / "statcast_2024_ohtani.csv"
    if not path.is_file():
        pytest.skip("the shared exports are not here")
    df = sc.read(path)
    bip = df[sc.balls_in_play(df)]
    return bip[bip["bat_speed"].notna()]


def test_adjustment_is_the_nearest_and_within_the_error(ohtani):
    # one attack-angle node: the move of the one contact's bat speed
    strict = infer_spin(ohtani, options=InferenceOptions(bat_speed_error=0.0,
                                                         attack_angle_nodes=1))
    loose = infer_spin(ohtani, options=InferenceOptions(attack_angle_nodes=1))
    s_ok = strict["inference_status"] == "converged"
    l_ok = loose["inference_status"] == "converged"
    assert (l_ok | ~s_ok).all()  # nothing the measured speed reproduces is lost
    # where the measured speed reproduces the ball it is not moved
    assert (loose.loc[s_ok, "bat_speed_adjustment"] == 0.0).all()
    moved = loose["bat_speed_adjustment"].fillna(0.0) != 0.0
    assert moved.any() and (loose.loc[moved, "bat_speed_adjustment"].abs() <= 5.0).all()
    assert (loose.loc[moved, "inferred"] == "nearest_bat_speed").all()
    used = loose.loc[moved, "bat_speed"] - ohtani.loc[moved, "bat_speed"]
    assert np.allclose(used, loose.loc[moved, "bat_speed_adjustment"])
    # the fallback moves the bat speed no further than the smallest move that works:
    # 10 % less than each adjustment leaves the ball out of reach (strict at that speed)
    shrunk = ohtani.loc[moved].copy()
    shrunk["bat_speed"] += 0.9 * loose.loc[moved, "bat_speed_adjustment"]
    again = infer_spin(shrunk, options=InferenceOptions(bat_speed_error=0.0,
                                                        attack_angle_nodes=1))
    assert (again["inference_status"] != "converged").mean() > 0.8
