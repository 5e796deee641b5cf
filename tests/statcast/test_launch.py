"""The launch direction found from where a ball came down: its flight lands along the
measured spray angle, a pulled ball left the bat less pulled, and a left-handed batter is
the mirror image."""

import numpy as np

from mcbat.bodies import BALL_PRESETS
from mcbat.statcast.launch import launch_spray
from mcbat.study.flight import FlightSettings, fly_launches

MPH, DEG, RPM = 0.44704, np.pi / 180, 2 * np.pi / 60
BALL = BALL_PRESETS["regulation"]


def test_the_flight_comes_down_along_the_measured_spray_angle():
    speed = np.array([95.0, 102.0, 108.0, 99.0, 104.0])
    angle = np.array([25.0, 30.0, 28.0, 35.0, 22.0])
    measured = np.array([-40.0, -20.0, 0.0, 18.0, 38.0])
    spray, back, side = launch_spray(speed, angle, measured, ["R"] * 5)
    out, status = fly_launches(FlightSettings(), BALL.mass, BALL.radius, speed * MPH,
                               angle * DEG, spray * DEG, back * RPM, side * RPM)
    landed = np.degrees(np.arctan2(out["landing_x"], out["landing_y"]))
    assert (status == 0).all()
    np.testing.assert_allclose(landed, measured, atol=0.05)
    # a right-handed batter's pulled balls hook towards the left-field line: they left
    # the bat less pulled than where they came down
    assert spray[0] > measured[0] and spray[1] > measured[1]


def test_a_left_handed_batter_is_the_mirror_image():
    speed, angle = np.array([101.0, 97.0]), np.array([27.0, 33.0])
    right, back_r, side_r = launch_spray(speed, angle, np.array([-30.0, 25.0]), ["R", "R"])
    left, back_l, side_l = launch_spray(speed, angle, np.array([30.0, -25.0]), ["L", "L"])
    np.testing.assert_allclose(left, -right, atol=1e-6)
    np.testing.assert_allclose(back_l, back_r, atol=1e-6)
    np.testing.assert_allclose(side_l, -side_r, atol=1e-6)
