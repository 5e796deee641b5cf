"""The spin averaged over the attack angles the data leave open (``attack_angle_nodes``):
it reduces to the one-contact inference when the attack angle is known, and on real
tracked balls in play it converges where the one assumed swing cannot and its backspin
rises with the launch angle as Nathan's average spin model of tracked balls does."""

from pathlib import Path

import numpy as np
import pytest

import mcbat.statcast as sc
from mcbat.inference import InferenceOptions, SpinAssumptions, infer_spin
from mcbat.inference.compare import NATHAN_SLOPE, backspin_slopes
from tests.inference.known_contacts import simulate_balls

SHARED = Path(__file__).parents[2] / ".." / "shared" / "data" / "statcast"
SPIN = ("backspin", "sidespin", "gyrospin", "spin_rate")


@pytest.mark.parametrize("measured", [False, True])
def test_a_known_attack_angle_gives_the_one_contact(measured):
    balls, truth = simulate_balls(6, seed=21, measured_swing=measured)
    known = SpinAssumptions(attack_angle_sd=0.0, attack_angle_error=0.0)
    out = infer_spin(balls, assumptions=known)
    assert (out["inference_status"] == "converged").all()
    for name in SPIN:
        np.testing.assert_allclose(out[name], truth[name], rtol=0,
                                   atol=1e-6 * truth["spin_rate"].max())
    np.testing.assert_allclose(out["undercut"], truth["undercut"], rtol=1e-6)


def test_the_mean_lies_among_the_contacts_that_give_the_ball():
    balls, _ = simulate_balls(6, seed=22, measured_swing=False)
    mean = infer_spin(balls)
    a = SpinAssumptions()
    singles = []
    for x in np.polynomial.hermite_e.hermegauss(5)[0]:
        one = SpinAssumptions(attack_angle=a.attack_angle + x * a.attack_angle_sd)
        singles.append(infer_spin(balls, assumptions=one,
                                  options=InferenceOptions(attack_angle_nodes=1)))
    back = np.array([s["backspin"].to_numpy() for s in singles])
    ok = mean["inference_status"] == "converged"
    assert ok.all()
    lo, hi = np.nanmin(back, axis=0), np.nanmax(back, axis=0)
    assert ((mean["backspin"] >= lo - 1e-6) & (mean["backspin"] <= hi + 1e-6)).all()
    assert (hi - lo > 100.0).all()  # the attack angle matters: a real average


def _tracked(name):
    path = SHARED / name
    if not path.is_file():
        pytest.skip("the shared exports are not here")
    df = sc.read(path)
    bip = df[sc.balls_in_play(df)]
    return bip[bip["bat_speed"].notna()]


FILES = ("statcast_2024_ohtani.csv", "statcast_2024_skubal.csv", "statcast_2025-05-01.csv")


@pytest.mark.parametrize("name", FILES)
def test_tracked_balls_in_play_converge(name):
    balls = _tracked(name)
    out = infer_spin(balls)
    assert (out["inference_status"] == "converged").mean() >= 0.95
    point = infer_spin(balls, options=InferenceOptions(attack_angle_nodes=1))
    assert (point["inference_status"] == "converged").mean() < 0.95


@pytest.fixture(scope="module")
def tracked_slopes():
    """``backspin_slopes`` of each tracked file's balls in play, inferred with the
    defaults."""
    return {name: backspin_slopes(balls, infer_spin(balls))
            for name, balls in ((n, _tracked(n)) for n in FILES)}


@pytest.mark.parametrize("name", FILES)
def test_backspin_slope_of_each_tracked_file_near_nathans(tracked_slopes, name):
    """Least squares of backspin on launch angle, 10-40 deg, one file's converged balls:
    within 15 % of Nathan's 120 rpm per degree."""
    assert 102.0 <= tracked_slopes[name].inferred <= 138.0, tracked_slopes[name]


@pytest.mark.parametrize("name", FILES)
def test_backspin_follows_nathans_model_on_the_same_balls(tracked_slopes, name):
    """Like for like: the slope within 5 % of Nathan's model evaluated on the same balls
    (whose spray angles rise with the launch angle), and the launch angle's coefficient
    with the spray angle held within 8 rpm/deg (two of its bootstrap errors) of his 120.
    The tangential restitution was fitted on the 2024 files; 2025-05-01 is out of its
    sample. With e_x = 0.28 every file fails the first (7-9 % above Nathan's)."""
    s = tracked_slopes[name]
    assert abs(s.inferred / s.nathan_same_balls - 1.0) < 0.05, s
    assert abs(s.inferred_spray_held - NATHAN_SLOPE) < 8.0, s
