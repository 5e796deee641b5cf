"""Spin inference: the contact behind a measured batted ball, through the game model.

Round trips run the game kernel forward on known contacts (``mcbat.api.solve_game``, the
path a single game case takes, independent of the inference's own input assembly) and
ask the inference to find them again from the pitch and the three launch numbers.
"""

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.inference import InferenceOptions, SpinAssumptions, infer_spin, predict_batted_balls
from tests.conftest import ROOT
from tests.inference.known_contacts import simulate_balls as _simulate

#: The attack angle taken as exact (one node): the contact that gives the ball is one.
EXACT = InferenceOptions(attack_angle_nodes=1)


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
    out = infer_spin(balls, options=EXACT)
    _check_round_trip(out, truth, "bat_speed")
    assert out.attrs["status_counts"]["converged"] == 12
    assert out.attrs["units"]["backspin"] == "rpm"


def test_round_trip_with_measured_bat_speed_infers_the_contact_position():
    balls, truth = _simulate(12, seed=4, measured_swing=True)
    out = infer_spin(balls, options=EXACT)
    _check_round_trip(out, truth, "from_barrel_end")
    np.testing.assert_array_equal(out["attack_angle"], balls["attack_angle"])


@pytest.mark.parametrize("measured_swing", [True, False])
def test_round_trip_with_each_balls_swing_plane(measured_swing):
    # each ball's bat at its own angle, given only through its plane's tilt: the inference
    # finds the contact again only if it rebuilds the bat from the tilt
    balls, truth = _simulate(10, seed=8, measured_swing=measured_swing, planes=True)
    out = infer_spin(balls, options=EXACT)
    _check_round_trip(out, truth, "from_barrel_end" if measured_swing else "bat_speed")
    assert out.attrs["swing_plane"] == len(balls)
    ball = predict_batted_balls(balls, undercut=truth["undercut"],
                                attack_direction=truth["attack_direction"],
                                bat_speed=truth["bat_speed"],
                                from_barrel_end=truth["from_barrel_end"])
    np.testing.assert_allclose(ball["launch_angle"], truth["launch_angle"], atol=1e-9)
    # without the plane every bat is the assumed one, and the balls are not found again
    assumed = infer_spin(balls, options=EXACT, use_swing_plane=False)
    assert assumed.attrs["swing_plane"] == 0
    gap = np.abs(assumed["undercut"] - truth["undercut"]).fillna(1.0)
    assert (gap > 1e-4).mean() > 0.5


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


def test_a_ball_fielded_behind_the_plate_is_solved_with_a_straightaway_launch():
    # hit coordinates behind the plate's line (a pop-up the catcher caught) give no launch
    # direction: the ball is solved as if it had left straightaway, and says so
    balls, _ = _simulate(3, seed=7, measured_swing=True)
    behind = balls.copy()
    behind.loc[1, "spray_angle"] = 162.0
    straight = balls.copy()
    straight.loc[1, "spray_angle"] = 0.0
    out, ref = infer_spin(behind, options=EXACT), infer_spin(straight, options=EXACT)
    assert out["spray_observed"].tolist() == [True, False, True]
    assert (out["inference_status"] == "converged").all()
    for name in ("backspin", "sidespin", "undercut", "attack_direction"):
        np.testing.assert_array_equal(out[name], ref[name])
    # the other balls keep their own spray: the same solution as without the row changed
    plain = infer_spin(balls, options=EXACT)
    np.testing.assert_array_equal(out.loc[[0, 2], "backspin"], plain.loc[[0, 2], "backspin"])
    assert not np.isclose(out.loc[1, "attack_direction"], plain.loc[1, "attack_direction"])
    assert out.attrs["units"]["spray_observed"] == ""


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
    end = infer_spin(balls, assumptions=SpinAssumptions(contact_side="end"), options=EXACT)
    assert (end["inference_status"] == "converged").all()
    np.testing.assert_allclose(end["from_barrel_end"], case_z, rtol=1e-6)
    handle = infer_spin(balls, options=EXACT)
    ok = handle["inference_status"] == "converged"
    assert (handle.loc[ok, "from_barrel_end"] > 0.1).all()


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
    their backspin rises with the launch angle as measured spin does (the attack angle
    taken as exact, so that each converged ball's one contact can be checked)."""
    from mcbat import statcast

    pitches = statcast.read(ROOT / "data" / "statcast_2020-09-03.csv")
    balls = pitches[statcast.balls_in_play(pitches)]
    out = infer_spin(balls, options=EXACT)
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


def test_the_inference_takes_the_impact_accuracy_as_one_solver_settings():
    from mcbat import SolverSettings
    from mcbat.errors import InputError

    tight = InferenceOptions(solver=SolverSettings(steps=12, tolerance=1e-10, max_steps=900))
    settings = tight.kernel_settings("handle")
    assert (settings.steps, settings.impact_tolerance, settings.max_steps) == (12, 1e-10, 900)
    with pytest.raises(InputError, match="^solver: must be a SolverSettings"):
        InferenceOptions(solver={"tolerance": 1e-10})
