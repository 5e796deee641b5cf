"""The pitch at the front of the plate, against computations that share no code with it:
the crossing time by root bracketing on ``y(t)``, the angles by ``arcsin``/``arctan``, and
mcbat's own game kernel rebuilding the velocity from the three numbers."""

import math
from importlib import resources

import numpy as np
import pytest
from scipy.optimize import brentq

from mcbat.core.swing.frames import Pitch, pitch_state
from mcbat.statcast import kinematics, read

FT_PER_M = 1.0 / 0.3048


@pytest.fixture(scope="module")
def real():
    """Every pitch of the shipped 2019 and 2020 exports with a full fit."""
    rows = []
    for name in ("statcast_2019_darvish.csv", "statcast_2020-09-03.csv"):
        import pandas as pd

        raw = pd.read_csv(resources.files("mcbat.data").joinpath(name), na_values=["null"],
                          low_memory=False)
        rows.append(raw[["vx0", "vy0", "vz0", "ax", "ay", "az"]].dropna())
    import pandas as pd

    return pd.concat(rows, ignore_index=True)


def _independent(vx0, vy0, vz0, ax, ay, az, y0=50.0, yf=17.0 / 12.0):
    """Crossing time by bracketing the root of y(t) - yf (brentq to 1e-15 s), then the
    velocity, speed (mph) and the angles by arcsin/arctan."""
    t = brentq(lambda t: y0 + vy0 * t + 0.5 * ay * t * t - yf, 0.0, 2.0, xtol=1e-15,
               rtol=4 * np.finfo(float).eps)
    vx, vy, vz = vx0 + ax * t, vy0 + ay * t, vz0 + az * t
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    vertical = math.degrees(math.asin(vz / speed))
    horizontal = math.degrees(math.atan(vx / -vy))
    return speed * 3600.0 / 5280.0, vertical, horizontal, (vx, vy, vz)


def test_plate_crossing_matches_an_independent_root_finder_on_every_real_pitch(real):
    speed, vertical, horizontal = kinematics.plate_crossing(*(real[c].to_numpy() for c in (
        "vx0", "vy0", "vz0", "ax", "ay", "az")))
    assert len(real) > 2900
    for i, row in enumerate(real.itertuples(index=False)):
        s, v, h, _ = _independent(*row)
        assert speed[i] == pytest.approx(s, abs=1e-9)
        assert vertical[i] == pytest.approx(v, abs=1e-9)
        assert horizontal[i] == pytest.approx(h, abs=1e-9)


def test_the_three_numbers_rebuild_the_velocity_in_mcbats_game_kernel(real):
    """speed, V, H fed to mcbat.core.swing.pitch_state give back the crossing velocity:
    the angles are the game keys' angles, signs included."""
    sample = real.iloc[::25]
    speed, vertical, horizontal = kinematics.plate_crossing(*(sample[c].to_numpy() for c in (
        "vx0", "vy0", "vz0", "ax", "ay", "az")))
    for i, row in enumerate(sample.itertuples(index=False)):
        _, _, _, v_ft = _independent(*row)
        ok, v, _ = pitch_state(Pitch(speed[i] * 0.44704, math.radians(vertical[i]),
                                     math.radians(horizontal[i]), 0.0, math.pi, 1.0, 1.0))
        assert ok
        assert np.allclose(np.array(v) * FT_PER_M, v_ft, rtol=0, atol=1e-9)


def test_signs_descending_is_negative_and_towards_first_base_is_positive():
    # straight down the middle, falling: V < 0, H = 0
    s, v, h = kinematics.plate_crossing(0.0, -130.0, -5.0, 0.0, 25.0, -20.0)
    assert v < 0 and h == 0.0
    # drifting towards +x (first-base side)
    _, _, h = kinematics.plate_crossing(3.0, -130.0, -5.0, 2.0, 25.0, -20.0)
    assert h > 0


def test_at_the_fit_plane_the_velocity_is_the_fit_velocity():
    s, v, h = kinematics.plate_crossing(4.0, -130.0, -6.0, -10.0, 28.0, -15.0,
                                        y_plate=kinematics.Y0_FT)
    assert s == pytest.approx(math.sqrt(16 + 130**2 + 36) * 3600 / 5280, abs=1e-12)
    assert v == pytest.approx(math.degrees(math.asin(-6 / math.sqrt(16 + 130**2 + 36))),
                              abs=1e-12)


def test_the_y_z_plane_convention_differs_by_less_than_a_twentieth_of_a_degree(real):
    """docs/statcast.md: the literature's VAA is atan(vz/vy), the angle in the y-z plane;
    mcbat's is the elevation of the velocity. On real pitches with |H| < 5 deg they agree to
    < 0.05 deg (about sin V cos V H^2 / 2)."""
    speed, vertical, horizontal = kinematics.plate_crossing(*(real[c].to_numpy() for c in (
        "vx0", "vy0", "vz0", "ax", "ay", "az")))
    yz = np.degrees(np.arctan(np.tan(np.radians(vertical)) / np.cos(np.radians(horizontal))))
    small = np.abs(horizontal) < 5
    assert small.sum() > 2500
    gap = np.abs(yz[small] - vertical[small])
    assert np.max(gap) < 0.05 and np.median(gap) < 0.01


def test_missing_or_impossible_fits_give_nan():
    s, v, h = kinematics.plate_crossing([np.nan, 1.0, 1.0], [-130.0, 10.0, -5.0],
                                        [-5.0, -5.0, -5.0], [0.0, 0.0, 0.0],
                                        [25.0, 25.0, 50.0], [-20.0, -20.0, -20.0])
    # NaN input; moving away from the plate; decelerating to rest before reaching it
    assert np.isnan(s).all() and np.isnan(v).all() and np.isnan(h).all()


def test_spray_angle_convention():
    # towards centre field, the right-field side, the left-field side; missing -> NaN
    x0, y0 = kinematics.HOME_PLATE_HC
    got = kinematics.spray_angle([x0, x0 + 50, x0 - 50, np.nan], [y0 - 100, y0 - 50,
                                                                    y0 - 50, 100.0])
    assert got[0] == 0.0 and got[1] == pytest.approx(45.0) and got[2] == pytest.approx(-45.0)
    assert np.isnan(got[3])


def test_the_tidy_table_uses_these_functions(real):
    df = read(resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv"))
    fit = df.dropna(subset=["pitch_speed"])
    assert len(fit) == len(df) == 2507
