"""Measured balls from known contacts, for the inference's tests: the game kernel run
forward (``mcbat.api.solve_game``, the path a single game case takes, independent of the
inference's own input assembly) on random pitches and swings."""

import math

import numpy as np
import pandas as pd

from mcbat.api import GameCase, solve_game
from mcbat.bodies import BALL_PRESETS, bat_preset
from mcbat.inference import SpinAssumptions

DEG = math.pi / 180
MPH = 0.44704
RPM = 60 / (2 * math.pi)
BAT = bat_preset("r161")
# without a measured swing the inference solves for the bat speed with the contact where it
# assumes it: the balls are made there
ASSUMED_CONTACT = SpinAssumptions().from_barrel_end


def simulate_balls(n, seed, measured_swing, planes=False):
    """Balls from known contacts: the tidy columns, and the truth. With ``planes`` each
    ball's bat has its own vertical angle (−45 to −15°) and the row the tilt of the plane
    its axis and the sweet spot's velocity span (``sin² tilt = sin² b + sin² a``)."""
    rng = np.random.default_rng(seed)
    rows, truth = [], []
    for k in range(n):
        hand = "R" if k % 2 == 0 else "L"
        attack = rng.uniform(0, 20) if measured_swing else 10.0
        vertical = rng.uniform(-45, -15) if planes else -30.0
        case = GameCase(
            ball=BALL_PRESETS["baseball"], bat=BAT, mu=0.5, handedness=hand,
            pitch_speed=rng.uniform(78, 98) * MPH, bat_speed=rng.uniform(62, 80) * MPH,
            vertical_approach_angle=rng.uniform(-9, -3) * DEG,
            horizontal_approach_angle=rng.uniform(-3, 3) * DEG,
            spin_rate=rng.uniform(1500, 2700) / RPM, spin_axis=rng.uniform(0, 360) * DEG,
            attack_angle=attack * DEG, attack_direction=rng.uniform(-20, 20) * DEG,
            vertical_bat_angle=vertical * DEG, undercut=rng.uniform(-0.025, 0.025),
            from_barrel_end=rng.uniform(0.17, 0.25) if measured_swing else ASSUMED_CONTACT)
        ball = solve_game(case).batted_ball
        row = {"pitch_speed": case.pitch_speed / MPH,
               "vertical_approach_angle": case.vertical_approach_angle / DEG,
               "horizontal_approach_angle": case.horizontal_approach_angle / DEG,
               "spin_rate": case.spin_rate * RPM, "spin_axis": case.spin_axis / DEG,
               "handedness": hand, "launch_speed": ball["launch_speed"],
               "launch_angle": ball["launch_angle"], "spray_angle": ball["spray_angle"]}
        if measured_swing:
            row.update(bat_speed=case.bat_speed / MPH, attack_angle=attack)
        if planes:
            row["swing_path_tilt"] = math.degrees(math.asin(math.sqrt(
                math.sin(vertical * DEG) ** 2 + math.sin(attack * DEG) ** 2)))
        rows.append(row)
        truth.append({"undercut": case.undercut, "bat_speed": case.bat_speed / MPH,
                      "from_barrel_end": case.from_barrel_end,
                      "attack_direction": case.attack_direction / DEG, **ball})
    return pd.DataFrame(rows), pd.DataFrame(truth)
