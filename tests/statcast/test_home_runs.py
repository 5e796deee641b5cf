"""Home-run calls at known fences: the Green Monster, a line drive that meets a wall while
rising, the same ball at sea level and at Coors Field's elevation."""

from pathlib import Path

import numpy as np
import pytest

from mcbat.bodies import BALL_PRESETS
from mcbat.statcast import parks
from mcbat.statcast.home_runs import home_run_call
from mcbat.statcast.launch import launch_spray
from mcbat.study.flight import FlightSettings, fly_launches, heights_at_distance

FT, MPH, DEG, RPM = 0.3048, 0.44704, np.pi / 180, 2 * np.pi / 60
BALL = BALL_PRESETS["regulation"]


def test_the_green_monster_is_310_ft_away_and_37_ft_high():
    distance, height = parks.fence("fenway_park", [-45.0])
    assert distance[0] == 310.0 and height[0] == 37.0


def test_a_call_is_the_height_where_the_ball_meets_the_fence():
    speeds, angles = np.array([88.0, 92.0, 96.0, 100.0]), np.array([24.0, 26.0, 28.0, 30.0])
    spray = np.full(4, -44.0)
    back = -763 + 120 * angles
    call = home_run_call(speeds, angles, spray, back, 0.0, "fenway_park")
    z, _ = heights_at_distance(FlightSettings(), BALL.mass, BALL.radius,
                               call["fence_distance"].to_numpy() * FT, speeds * MPH,
                               angles * DEG, spray * DEG, back * RPM, 0.0)
    np.testing.assert_allclose(call["height_at_fence"], z / FT)
    assert (call["home_run"].to_numpy(bool) == (z / FT > 37.0)).all()
    assert call["home_run"].any() and not call["home_run"].all()  # the wall decides
    assert call.attrs["units"]["clearance"] == "ft"


def test_a_line_drive_that_meets_the_wall_rising_is_no_home_run():
    # 110 mph at 14 deg down the left-field line: it would carry well past 310 ft, but
    # it reaches the Green Monster below its top
    out, _ = fly_launches(FlightSettings(), BALL.mass, BALL.radius, 110 * MPH, 14 * DEG,
                          -44 * DEG, 1000 * RPM, 0.0)
    assert out["hit_distance"][0] / FT > 330.0
    call = home_run_call(110.0, 14.0, -44.0, 1000.0, 0.0, "fenway_park").iloc[0]
    assert 0 < call.height_at_fence < 37.0 and not call.home_run


def test_a_sliced_fly_ball_meets_the_fence_where_it_comes_down():
    # An opposite-field fly ball of a right-handed batter, measured coming down at 42.8 deg
    # (near Citi Field's right-field line, whose fence is 333 ft away there), slices about
    # 14 deg in flight: launched at 29 deg, where the fence is 370 ft. It meets the fence
    # near the line, so its call is decided there (13 ft short, a chance with the flight's
    # scatter), not at the fence of its launch direction (50 ft short, no chance).
    spray, back, side = launch_spray([94.4], [37.0], [42.8], ["R"])
    assert 27.0 < spray[0] < 31.0
    call = home_run_call(94.4, 37.0, spray, back, side, "citi_field", scatter_ft=13.0).iloc[0]
    near_line, launch_direction = parks.fence("citi_field", [42.8, spray[0]])[0]
    assert launch_direction - near_line > 30.0
    assert abs(call.fence_distance - near_line) < 5.0
    assert -20.0 < call.margin < -5.0 and 0.05 < call.home_run_probability < 0.35


def test_the_same_ball_clears_coors_field_but_not_at_sea_level():
    # a ball that dies at the warning track at sea level carries over Coors' fence
    speed, angle = 102.0, 29.0
    back = -763 + 120 * angle
    coors = parks.park_value(["coors_field"], "elevation_ft")[0]
    at_sea = home_run_call(speed, angle, 0.0, back, 0.0, "coors_field").iloc[0]
    at_coors = home_run_call(speed, angle, 0.0, back, 0.0, "coors_field",
                             per_ball={"elevation": np.array([coors * FT])}).iloc[0]
    assert coors > 5000
    assert not at_sea.home_run and at_coors.home_run


def test_an_unknown_fence_height_gives_no_call():
    # Sutter Health Park's fence distances are published, its heights are not
    call = home_run_call(110.0, 30.0, 0.0, 2800.0, 0.0, "sutter_health_park")
    assert call["fence_distance"].iloc[0] == 403.0 and np.isnan(call["fence_height"].iloc[0])
    assert call["home_run"].isna().all()


# --- real balls against the fences ---------------------------------------------------

FENWAY_EXCERPT = Path(__file__).parent / "data" / "statcast_2019_fenway_deep_excerpt.csv"
_CAUGHT = ("field_out", "sac_fly", "double_play", "sac_fly_double_play", "triple_play")


def _fenway_balls():
    from mcbat.statcast import reader
    return reader.read(FENWAY_EXCERPT)


def test_real_caught_balls_land_short_of_fenways_fence_and_home_runs_beyond_it():
    # Every home run and every ball caught in the air of >= 330 ft of the Red Sox' 2019
    # home games (tests/statcast/data/README.md). A caught ball must come down short of the
    # wall, a home run's projected distance lies beyond it; the earlier five-point fence cut
    # 15 ft inside the Green Monster's curve and left 41 of these 266 balls inconsistent.
    balls = _fenway_balls()
    fence_ft, _ = parks.fence(parks.park_of(balls["home_team"], balls["game_date"]),
                              balls["spray_angle"], balls["game_date"])
    dist = balls["hit_distance_sc"].to_numpy(float)
    home_run = (balls["events"] == "home_run").to_numpy(bool)
    caught = balls["events"].isin(_CAUGHT).to_numpy(bool)
    assert home_run.sum() == 109 and caught.sum() == 157
    wrong = (home_run & (dist < fence_ft)) | (caught & (dist > fence_ft))
    assert wrong.mean() <= 0.05, int(wrong.sum())


@pytest.mark.xfail(strict=True, reason="the flight under-calls the Green Monster's home "
                   "runs (90 called, 91 expected, of 109): open, docs/parks-and-weather.md")
def test_real_fenway_calls_match_the_measured_home_runs():
    from mcbat.statcast.replay import replay
    out = replay(_fenway_balls())
    called = out["actual_home_run"].astype("boolean")
    assert not called.isna().any()
    called = called.to_numpy(bool)
    measured = (out["events"] == "home_run").to_numpy(bool)
    # the flight's own scatter (~14 ft at the wall) leaves some wrong calls either way
    assert abs(called.sum() - measured.sum()) <= 0.15 * measured.sum()
    caught = out["events"].isin(_CAUGHT).to_numpy(bool)
    assert (called & caught).sum() <= 0.10 * caught.sum()
