"""The game preset's tangential compliance against the laboratory: a bat swung at a
stationary baseball (Kensrud, Nathan & Smith, Am. J. Phys. 85, 503 (2017), arXiv
1610.03464: bat speeds 63-88 mph, launch angles 0-30 deg) leaves the ball with a spin
"up to 40 % greater than would be obtained by rolling contact of rigid bodies"."""

import dataclasses
import math

import pytest

from mcbat.api import GameCase, solve_game
from mcbat.bodies import BALL_PRESETS, bat_preset
from mcbat.bodies.restitution import GAME_E_X, GAME_RESTITUTION

MPH = 0.44704


def _spin(bat_speed_mph, undercut, e_x):
    case = GameCase(ball=BALL_PRESETS["baseball"], bat=bat_preset("r161"), mu=0.5,
                    pitch_speed=0.01, bat_speed=bat_speed_mph * MPH, attack_angle=0.0,
                    vertical_bat_angle=0.0, undercut=undercut, from_barrel_end=0.1524,
                    restitution=dataclasses.replace(GAME_RESTITUTION, e_x=e_x))
    return solve_game(case).batted_ball


@pytest.mark.parametrize("bat_speed", [63.0, 75.0, 88.0])
@pytest.mark.parametrize("undercut", [0.005, 0.01, 0.02])
def test_spin_above_rolling_by_at_most_the_measured_forty_percent(bat_speed, undercut):
    rigid = _spin(bat_speed, undercut, 0.0)
    compliant = _spin(bat_speed, undercut, GAME_E_X)
    assert 0.0 < compliant["launch_angle"] < 30.0
    ratio = compliant["backspin"] / rigid["backspin"]
    assert 1.0 < ratio <= 1.4, ratio


def test_the_forty_percent_bound_can_fail():
    """A compliance well above the laboratory's (e_x = 0.6) breaks the bound."""
    ratio = _spin(75.0, 0.01, 0.6)["backspin"] / _spin(75.0, 0.01, 0.0)["backspin"]
    assert ratio > 1.4 and math.isfinite(ratio)
