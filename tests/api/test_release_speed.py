"""pitch.release_speed: a game's pitch given at release (Statcast's release_speed), flown
to the front of the plate with Nathan's drag (mcbat.api.pitch.plate_speed); checked
against Statcast's own 9-parameter fit of real pitches."""

import json
import math
from importlib import resources

import numpy as np
import pandas as pd
import pytest

from mcbat.api import case_from_dict, solve_any
from mcbat.api.pitch import DEFAULT_EXTENSION, plate_speed
from mcbat.errors import InputError
from mcbat.statcast.kinematics import plate_crossing

MPH, FT, RPM = 0.44704, 0.3048, math.pi / 30

GAME = {"bat": {"preset": "r161"}, "mu": 0.5,
        "pitch": {"speed": 94, "vertical_approach_angle": -6, "spin_rate": 2300},
        "swing": {"bat_speed": 72, "attack_angle": 10},
        "contact": {"undercut": {"value": 0.5, "unit": "in"}}}


def _game(**pitch):
    case = json.loads(json.dumps(GAME))
    del case["pitch"]["speed"]
    case["pitch"].update(pitch)
    return case


def test_a_94_mph_release_is_slower_at_the_plate_and_so_is_the_batted_ball():
    at_plate = solve_any(case_from_dict(GAME))
    released = solve_any(case_from_dict(_game(release_speed=94)))
    plate = math.hypot(*released.pitch_velocity) / MPH
    assert plate == pytest.approx(plate_speed(94 * MPH, spin_rate=2300 * RPM) / MPH,
                                  rel=1e-12)
    assert 84 < plate < 89 < math.hypot(*at_plate.pitch_velocity) / MPH
    assert released.launch_speed < at_plate.launch_speed


def test_the_extension_shortens_the_flight():
    near = plate_speed(94 * MPH, 7.5 * FT)
    far = plate_speed(94 * MPH, 5.0 * FT)
    assert far < plate_speed(94 * MPH) < near < 94 * MPH
    assert plate_speed(94 * MPH) == plate_speed(94 * MPH, DEFAULT_EXTENSION)
    case = case_from_dict(_game(release_speed=94, extension=7.5, spin_rate=0))
    assert case.pitch_speed == pytest.approx(near, rel=1e-12)


def test_spin_adds_drag():
    assert plate_speed(94 * MPH, spin_rate=2500 * RPM) < plate_speed(94 * MPH)


@pytest.mark.parametrize("pitch, key", [
    ({"speed": 86, "release_speed": 94}, "pitch.speed"),
    ({}, "pitch.speed"),
    ({"speed": 86, "extension": 6.5}, "pitch.extension"),
    ({"release_speed": 94, "extension": 60}, "pitch.extension"),     # beyond [3, 9] ft
    ({"release_speed": 150}, "pitch.release_speed"),                 # beyond [25, 110] mph
    ({"release_speed": {"value": 15, "unit": "mph"}}, "pitch.release_speed"),  # falls short
])
def test_exactly_one_speed_and_a_plausible_release(pitch, key):
    case = json.loads(json.dumps(GAME))
    case["pitch"] = {"spin_rate": 2300, **pitch}
    with pytest.raises(InputError) as info:
        case_from_dict(case)
    assert info.value.field == key


def test_release_speed_against_statcasts_fit_of_real_pitches():
    """The 2,507 pitches of 2020-09-03 (Statcast's release_speed, release_extension,
    release_spin_rate) converted by the flight; Statcast's plate speed from its own
    constant-acceleration fit (vx0..az). The conversion is 0.97 mph slower at the median
    (middle half -1.41..-0.58, 5-95 % -2.08..-0.02 mph; Nathan's spin-dependent drag,
    0.0292 per 1000 rpm, is more than these pitches show): stated tolerance, the median
    within 1.25 mph and 90 % of the pitches within 2.5 mph."""
    with resources.as_file(resources.files("mcbat.data") / "statcast_2020-09-03.csv") as p:
        rows = pd.read_csv(p)
    cols = ["release_speed", "release_extension", "release_spin_rate",
            "vx0", "vy0", "vz0", "ax", "ay", "az"]
    rows = rows.dropna(subset=cols)
    assert len(rows) == 2507
    statcast, _, _ = plate_crossing(*(rows[c] for c in cols[3:]))
    ours = np.array([plate_speed(r.release_speed * MPH, r.release_extension * FT,
                                 r.release_spin_rate * RPM) / MPH
                     for r in rows.itertuples()])
    diff = ours - statcast
    assert abs(np.median(diff)) < 1.25
    assert np.mean(np.abs(diff) <= 2.5) >= 0.9
    # and the speed the air takes away is of the size Statcast's fit gives (7.3 mph)
    lost = np.median(rows["release_speed"] - ours)
    assert 0.8 < lost / np.median(rows["release_speed"] - statcast) < 1.25
