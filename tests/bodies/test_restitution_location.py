"""The location factor of ``e*`` (``mcbat.bodies.restitution``) and what the game presets
make of it: the collision efficiency ``q`` of a square hit peaks at the sweet spot and
falls towards the barrel end and towards the handle (docs/batting.md, "Where the ball
meets the bat"). No measured table of a wood bat's COR against the impact point is
shipped; these tests hold the presets to the shape that the assumed table was built for.
"""

import numpy as np
import pytest

import mcbat
from mcbat.api import GameCase, solve_game
from mcbat.bodies.restitution import LOCATION_TABLES, Restitution, location_table
from mcbat.errors import InputError
from tests.conftest import ROOT

IN = 0.0254
MPH = 0.44704
PRESETS = ("game_fastball", "game_curveball", "mlb_balls_in_play")
# The presets' contact range (studies/*.toml, [contact] from_barrel_end: 0.5-18 in).
Z_IN = np.arange(0.5, 18.01, 0.5)


def _preset(name):
    """The preset's ball, bat and restitution (its constant ``[restitution]`` values and
    its location table), as a study file gives them."""
    study = mcbat.load_study(ROOT / "studies" / f"{name}.toml")
    fixed = {}
    for key, dist in study.inputs.items():
        if key.startswith("restitution."):
            low, high = dist.support()
            assert low == high, f"{name}: {key} is drawn; this test needs it fixed"
            fixed[key.split(".", 1)[1]] = low
    return study.ball, study.bat, Restitution(location=study.restitution.location, **fixed)


def _head_on_q(ball, bat, restitution, pitch_mph, bat_mph):
    """``q`` of a square, head-on hit (no undercut, level swing, no pitch spin) at each
    distance of ``Z_IN`` from the barrel end."""
    return np.array([
        solve_game(GameCase(ball=ball, bat=bat, pitch_speed=pitch_mph * MPH,
                            bat_speed=bat_mph * MPH, mu=0.5, from_barrel_end=z * IN,
                            restitution=restitution)).collision_efficiency
        for z in Z_IN])


@pytest.mark.parametrize("name", PRESETS)
def test_preset_q_peaks_at_the_sweet_spot_and_falls_on_both_sides(name):
    ball, bat, rest = _preset(name)
    assert rest.location is not None, f"{name} has no location table"
    # the presets' spread of pitch and bat speeds (78-94 mph pitches; swings of one sd
    # either side of the fitted 69.5 mph, and the 71.5 mph league average)
    for pitch_mph in (78.0, 86.0, 94.0):
        for bat_mph in (63.0, 71.5, 76.0):
            q = _head_on_q(ball, bat, rest, pitch_mph, bat_mph)
            peak = int(np.argmax(q))
            where = (name, pitch_mph, bat_mph, Z_IN[peak])
            # the sweet zone: 5-7 in from the barrel end (bat tracking's sweet spot is at
            # 6 in; the barrel-end nodes of the second and first bending modes of a wood
            # bat lie near 4.5 and 6.5 in)
            assert 5.0 <= Z_IN[peak] <= 7.0, where
            # strictly falling on both sides over the whole contact range
            assert np.all(np.diff(q[:peak + 1]) > 0), where
            assert np.all(np.diff(q[peak:]) < 0), where
            # and by a margin at the ends of the range: weak contact off the barrel
            assert q[0] < 0.5 * q[peak] and q[-1] < 0.5 * q[peak], (where, q[0], q[-1])


@pytest.mark.parametrize("name", PRESETS)
def test_preset_q_at_the_peak_is_a_wood_bats(name):
    # at the reference hit of docs/batting.md (86 mph pitch, 71.5 mph swing): q ~ 0.20
    # at a wood bat's sweet spot (Nathan, Am. J. Phys. 71, 134 (2003)) to ~0.22
    # (Statcast's squared-up examples)
    ball, bat, rest = _preset(name)
    q = _head_on_q(ball, bat, rest, 86.0, 71.5)
    assert 0.20 <= q.max() <= 0.23, q.max()


def test_the_same_bat_without_the_table_peaks_towards_the_handle():
    # what the table is for: with e* independent of the place, the rigid bat's effective
    # mass (largest near its CM, ~11 in from the R161's barrel end) moves the best contact
    # well past the sweet spot
    ball, bat, rest = _preset("game_fastball")
    bare = Restitution(e_ref=rest.e_ref, e_slope=rest.e_slope,
                       e_speed_ref=rest.e_speed_ref, e_x=rest.e_x)
    q = _head_on_q(ball, bat, bare, 86.0, 71.5)
    assert Z_IN[int(np.argmax(q))] > 9.0


# ------------------------------------------------------------------------- the tables

@pytest.mark.parametrize("name", list(LOCATION_TABLES))
def test_every_shipped_table_reads_and_is_a_factor(name):
    z, f = location_table(name)
    assert z.ndim == f.ndim == 1 and z.size == f.size >= 2
    assert np.all(np.diff(z) > 0) and z[0] == 0.0
    assert np.all((f > 0.0) & (f <= 1.0)) and f.max() == 1.0


def test_location_factor_interpolates_linearly_and_holds_beyond_the_ends():
    rest = Restitution(e_ref=0.5, location="assumed")
    z, f = location_table("assumed")
    mid = 0.5 * (z[-2] + z[-1])
    assert rest.location_factor(mid) == pytest.approx(0.5 * (f[-2] + f[-1]), abs=1e-15)
    assert rest.location_factor(z[-1] + 0.5) == f[-1]
    assert rest.location_factor(-0.01) == f[0]
    assert isinstance(rest.location_factor(0.1), float)
    got = rest.location_factor(np.array([0.0, z[-1]]))
    assert isinstance(got, np.ndarray) and np.array_equal(got, [f[0], f[-1]])
    assert Restitution(e_ref=0.5).location_factor(0.1) == 1.0


def test_an_unknown_table_is_refused_by_name():
    with pytest.raises(InputError, match="location") as err:
        Restitution(e_ref=0.5, location="measured")
    assert "assumed" in str(err.value)
