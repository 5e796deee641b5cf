"""Home-run calls at known fences: the Green Monster, a line drive that meets a wall while
rising, the same ball at sea level and at Coors Field's elevation."""

import numpy as np

from mcbat.bodies import BALL_PRESETS
from mcbat.statcast import parks
from mcbat.statcast.home_runs import home_run_call
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
