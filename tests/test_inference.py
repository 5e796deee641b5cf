"""Spin inference: the contact behind a measured batted ball, through the game model.

Round trips run the game kernel forward on known contacts (``mcbat.api.solve_game``, the
path a single game case takes, independent of the inference's own input assembly) and
ask the inference to find them again from the pitch and the three launch numbers.
"""

import math

import numpy as np
import pandas as pd
import pytest

from mcbat.api import GameCase, solve_game
from mcbat.bodies import BALL_PRESETS, bat_preset
from mcbat.errors import InputError
from mcbat.inference import SpinAssumptions, infer_spin, predict_batted_balls
from tests.conftest import ROOT

DEG = math.pi / 180
MPH = 0.44704
RPM = 60 / (2 * math.pi)
BAT = bat_preset("r161")


def _simulate(n, seed, measured_swing):
    """Balls from known contacts: the tidy columns, and the truth."""
    rng = np.random.default_rng(seed)
    rows, truth = [], []
    for k in range(n):
        hand = "R" if k % 2 == 0 else "L"
        attack = rng.uniform(0, 20) if measured_swing else 10.0
        case = GameCase(
            ball=BALL_PRESETS["baseball"], bat=BAT, mu=0.5, handedness=hand,
            pitch_speed=rng.uniform(78, 98) * MPH, bat_speed=rng.uniform(62, 80) * MPH,
            vertical_approach_angle=rng.uniform(-9, -3) * DEG,
            horizontal_approach_angle=rng.uniform(-3, 3) * DEG,
            spin_rate=rng.uniform(1500, 2700) / RPM, spin_axis=rng.uniform(0, 360) * DEG,
            attack_angle=attack * DEG, attack_direction=rng.uniform(-20, 20) * DEG,
            vertical_bat_angle=-30 * DEG, undercut=rng.uniform(-0.025, 0.025),
            from_barrel_end=rng.uniform(0.17, 0.25) if measured_swing else 0.1524)
        ball = solve_game(case).batted_ball
        row = {"pitch_speed": case.pitch_speed / MPH,
               "vertical_approach_angle": case.vertical_approach_angle / DEG,
               "horizontal_approach_angle": case.horizontal_approach_angle / DEG,
               "spin_rate": case.spin_rate * RPM, "spin_axis": case.spin_axis / DEG,
               "handedness": hand, "launch_speed": ball["launch_speed"],
               "launch_angle": ball["launch_angle"], "spray_angle": ball["spray_angle"]}
        if measured_swing:
            row.update(bat_speed=case.bat_speed / MPH, attack_angle=attack)
        rows.append(row)
        truth.append({"undercut": case.undercut, "bat_speed": case.bat_speed / MPH,
                      "from_barrel_end": case.from_barrel_end,
                      "attack_direction": case.attack_direction / DEG, **ball})
    return pd.DataFrame(rows), pd.DataFrame(truth)


def _check_round_trip(out, truth, inferred):
    assert (out["inference_status"] == "converged").all(), out["inference_status"].tolist()
    assert (out["inferred"] == inferred).all()
    for name in ("undercut", "bat_speed", "from_barrel_end"):
        np.testing.assert_allclose(out[name], truth[name], rtol=1e-6, atol=0)
    np.testing.assert_allclose(out["attack_direction"], truth["attack_direction"], rtol=0,
                               atol=1e-6)
    for name in ("backspin", "sidespin", "gyrospin", "spin_rate"):
        np.testing.assert_allclose(out[name], truth[name], rtol=0,
                                   atol=1e-6 * truth["spin_rate"].max())


def test_round_trip_infers_bat_speed_undercut_and_attack_direction():
    balls, truth = _simulate(12, seed=3, measured_swing=False)
    out = infer_spin(balls)
    _check_round_trip(out, truth, "bat_speed")
    assert out.attrs["status_counts"]["converged"] == 12
    assert out.attrs["units"]["backspin"] == "rpm"


def test_round_trip_with_measured_bat_speed_infers_the_contact_position():
    balls, truth = _simulate(12, seed=4, measured_swing=True)
    out = infer_spin(balls)
    _check_round_trip(out, truth, "from_barrel_end")
    np.testing.assert_array_equal(out["attack_angle"], balls["attack_angle"])


def test_predict_batted_balls_is_the_forward_model_of_the_inference():
    balls, truth = _simulate(4, seed=5, measured_swing=False)
    ball = predict_batted_balls(balls, undercut=truth["undercut"],
                                attack_direction=truth["attack_direction"],
                                bat_speed=truth["bat_speed"])
    assert (ball["status"] == "ok").all()
    for name in ("launch_speed", "launch_angle", "spray_angle", "backspin"):
        np.testing.assert_allclose(ball[name], truth[name], rtol=1e-12, atol=1e-9)


def test_a_launch_speed_beyond_the_bat_speed_is_no_solution_with_nan_spin():
    balls, _ = _simulate(3, seed=6, measured_swing=True)
    balls.loc[1, "launch_speed"] = 160.0  # far beyond q P + (1 + q) V for these swings
    out = infer_spin(balls)
    assert out.loc[1, "inference_status"] == "no_solution"
    assert np.isnan(out.loc[1, ["backspin", "sidespin", "gyrospin", "undercut"]]
                    .astype(float)).all()
    assert out.attrs["status_counts"]["no_solution"] == 1
    assert (out.drop(index=1)["inference_status"] == "converged").all()


def test_the_end_side_of_the_bat_is_a_second_root():
    """With a measured bat speed the launch speed has two contact positions; the end
    side's root is found when asked for."""
    balls, truth = _simulate(4, seed=8, measured_swing=True)
    case_z = 0.07  # between the barrel end and the launch speed's maximum
    ball = predict_batted_balls(balls, undercut=truth["undercut"],
                                attack_direction=truth["attack_direction"],
                                from_barrel_end=case_z)
    balls = balls.assign(launch_speed=ball["launch_speed"], launch_angle=ball["launch_angle"],
                         spray_angle=ball["spray_angle"])
    end = infer_spin(balls, assumptions=SpinAssumptions(contact_side="end"))
    assert (end["inference_status"] == "converged").all()
    np.testing.assert_allclose(end["from_barrel_end"], case_z, rtol=1e-6)
    handle = infer_spin(balls)
    ok = handle["inference_status"] == "converged"
    assert (handle.loc[ok, "from_barrel_end"] > 0.1).all()


def test_missing_column_names_it():
    balls, _ = _simulate(1, seed=9, measured_swing=False)
    with pytest.raises(InputError, match="^spray_angle: missing column"):
        infer_spin(balls.drop(columns="spray_angle"))


@pytest.mark.parametrize("column, value, message", [
    ("launch_speed", np.inf, "^launch_speed: must be finite"),
    ("pitch_speed", -3.0, "^pitch_speed: must be > 0 mph, got -3.0 in row 0"),
    ("launch_angle", 95.0, "^launch_angle: must lie within"),
    ("handedness", "S", '^handedness: must be "R" or "L"'),
    ("spin_rate", "fast", "^spin_rate: must be numbers"),
])
def test_bad_values_name_the_field(column, value, message):
    balls, _ = _simulate(2, seed=10, measured_swing=False)
    balls[column] = balls[column].astype(object)
    balls.loc[0, column] = value
    with pytest.raises(InputError, match=message):
        infer_spin(balls)


def test_nan_rows_are_flagged_and_counted_or_raised():
    balls, truth = _simulate(3, seed=11, measured_swing=False)
    balls.loc[2, "launch_angle"] = np.nan
    out = infer_spin(balls)
    assert out.loc[2, "inference_status"] == "missing_input"
    assert np.isnan(out.loc[2, "backspin"])
    assert out.attrs["status_counts"]["missing_input"] == 1
    assert (out.loc[:1, "inference_status"] == "converged").all()
    with pytest.raises(InputError, match="^launch_angle: missing value"):
        infer_spin(balls, missing="raise")


def test_an_absent_spin_axis_is_the_stated_default():
    balls, _ = _simulate(2, seed=12, measured_swing=False)
    with_default = infer_spin(balls.assign(spin_axis=np.nan))
    assumed = infer_spin(balls.assign(spin_axis=180.0))
    absent = infer_spin(balls.drop(columns="spin_axis"))
    pd.testing.assert_frame_equal(with_default, assumed)
    pd.testing.assert_frame_equal(absent, assumed)


def test_real_balls_in_play():
    """The shipped Statcast day (data/README.md): most balls in play are reproduced, and
    their backspin rises with the launch angle as measured spin does."""
    from mcbat import statcast

    pitches = statcast.read(ROOT / "data" / "statcast_2020-09-03.csv")
    balls = pitches[statcast.balls_in_play(pitches)]
    out = infer_spin(balls)
    counts = out.attrs["status_counts"]
    usable = len(balls) - counts["missing_input"]
    assert counts["converged"] >= 0.85 * usable
    ok = out["inference_status"] == "converged"
    la = balls.loc[ok, "launch_angle"]
    spin = out.loc[ok, "backspin"]
    assert spin[(la > 20) & (la < 35)].median() > 1000
    assert spin[la < -10].median() < -1000
    # each converged ball reproduces its launch numbers through the forward model
    sub = balls[ok]
    again = predict_batted_balls(sub, undercut=out.loc[ok, "undercut"],
                                 attack_direction=out.loc[ok, "attack_direction"],
                                 bat_speed=out.loc[ok, "bat_speed"])
    np.testing.assert_allclose(again["launch_speed"], sub["launch_speed"], rtol=1e-8)
    np.testing.assert_allclose(again["launch_angle"], sub["launch_angle"], atol=1e-6)
    np.testing.assert_allclose(again["backspin"], spin, rtol=1e-12)


def test_cli_infer_writes_the_balls_and_their_spin(tmp_path, capsys):
    import json

    import pyarrow.parquet as pq

    from mcbat.cli import main

    out = tmp_path / "spin.parquet"
    assert main(["infer", str(ROOT / "data" / "statcast_2019_darvish.csv"), "--out",
                 str(out)]) == 0
    text = capsys.readouterr().out
    assert "balls in play: converged" in text and f"written: {out}" in text
    table = pq.read_table(out)
    meta = json.loads(table.schema.metadata[b"mcbat.inference"])
    assert meta["units"]["backspin"] == "rpm" and meta["units"]["launch_speed"] == "mph"
    df = table.to_pandas()
    assert len(df) == sum(meta["status_counts"].values())
    assert {"hit_distance_sc", "launch_angle", "backspin", "inference_status"} <= set(df)


def test_cli_infer_refuses_a_bad_output_before_any_work(tmp_path, capsys):
    from mcbat.cli import main

    code = main(["infer", str(ROOT / "data" / "statcast_2019_darvish.csv"), "--out",
                 str(tmp_path / "spin.csv")])
    assert code == 2
    assert "--out: unsupported file type '.csv'" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
