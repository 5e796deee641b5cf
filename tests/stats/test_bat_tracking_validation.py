"""``python -m validation bat_tracking``: studies/bat_tracking.toml's contact fitted to
tracked balls in play and judged on games no fit saw.

The day of 2025-05-01 is cut into two parts of its games; each part is judged by a fit to
the two 2024 exports and the other part (cross-fitting), and the two judgements are pooled:
every one of the 572 rows is judged by a fit that never saw its game. The swing errors and
the contact's bat-speed trend are the study's (the scan that chose them,
``python -m validation bat_tracking --fit ... --cross ...``, is not repeated here), so the
test runs two contact fits.
"""

import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT.parent / "shared" / "data" / "statcast"
FIT = ["statcast_2024_skubal.csv", "statcast_2024_ohtani.csv"]
CROSS = "statcast_2025-05-01.csv"
POOLED = ("out of sample", f"{CROSS} (cross-fitted, 2 folds)")
STUDY = tomllib.loads((ROOT / "studies" / "bat_tracking.toml").read_text())

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not all((DATA / f).exists() for f in [*FIT, CROSS]),
                                 reason="the shared Statcast exports are absent")]


def _study_errors():
    errors = {k: v["value"] for k, v in STUDY["pitches"]["swing_error"].items()}
    return errors, STUDY["contact"]["bat_speed_trend"]["from_barrel_end"]["value"]


@pytest.fixture(scope="module")
def outcome():
    from validation.bat_tracking import run

    errors, trend = _study_errors()
    return run(FIT, [], samples=100000, seed=2025, errors=errors, trend=trend, cross=CROSS)


def test_study_contact_is_the_fit_that_left_its_games_out(outcome):
    # fold 2 judges the games the study ships (part 2 of 2): its fit is the study's contact,
    # to a tenth of the fit's error (the fit starts from the study's values, and its
    # template draws depend a little on where they start)
    fold = outcome["folds"][1]
    assert fold["fit_files"] == [*FIT, f"{CROSS}#1/2"]
    for p in fold["parameters"]:
        section, key, field = p["name"].split(".")
        tolerance = 0.1 * min(p["lower_error"], p["upper_error"])
        assert abs(STUDY[section][key][field] - p["value"]) <= tolerance, p


def test_cross_fitted_distributions(outcome):
    r = outcome["results"][POOLED]
    assert r["rows"] == 572
    assert r["ks_launch_speed"] <= 0.05
    assert r["ks_launch_angle"] <= 0.05


def test_cross_fitted_launch_speed_calibrated(outcome):
    r = outcome["results"][POOLED]
    assert 0.07 <= r["launch_speed_above_p90"] <= 0.13
    assert 0.07 <= r["launch_speed_below_p10"] <= 0.13


def test_cross_fitted_launch_angle_calibrated(outcome):
    r = outcome["results"][POOLED]
    assert 0.07 <= r["launch_angle_above_p90"] <= 0.13
    assert 0.07 <= r["launch_angle_below_p10"] <= 0.13


def test_cross_fitted_70_75_mph_bin(outcome):
    b = {x["bin"]: x for x in outcome["results"][POOLED]["bat_speed_bins"]}["70-75"]
    assert b["rows"] >= 100
    assert abs(b["model"] - b["measured"]) <= 2.0


@pytest.mark.xfail(strict=True, reason="the 65-70 mph bin of 2025-05-01: measured 89.0 +- "
                   "1.0 mph (q 0.141 against 0.11-0.12 in the neighbouring bins and in the "
                   "other files), model 86.5 mph (docs/bat_tracking.md)")
def test_cross_fitted_65_70_mph_bin(outcome):
    b = {x["bin"]: x for x in outcome["results"][POOLED]["bat_speed_bins"]}["65-70"]
    assert b["rows"] >= 100
    assert abs(b["model"] - b["measured"]) <= 2.0


def test_cross_fitted_launch_angle_follows_the_attack_angle(outcome):
    # the measured slope is 0.78 +- 0.15 (bootstrap); the model, given the measured swings
    # and their fitted errors, must lie within two of its errors
    r = outcome["results"][POOLED]
    assert abs(r["slopes_model"][1] - r["slopes_data"][1]) <= 0.30


def test_cross_fitted_launch_speed_follows_where_the_pitch_crossed(outcome):
    # measured, the launch speed of pitches more than 0.6 ft inside or away is 12-13 mph
    # below that over the plate; a contact that ignored the pitch's location missed the
    # inside bin by 9 mph and the outside one by 6 (docs/bat_tracking.md, (g))
    r = outcome["results"][POOLED]
    bins = {b["bin"]: b for b in r["plate_x_bins"]}
    for name in ("-10.0 to -0.6", "+0.6 to +10.0"):
        b = bins[name]
        assert b["rows"] >= 60
        assert abs(b["model"] - b["measured"]) <= 3 * b["se"] + 1.0, b
    assert r["plate_x_chi2"] <= 30.0


def test_cross_fitted_launch_angle_follows_the_pitchs_height(outcome):
    # measured, the launch angle rises from 8 deg below 1.8 ft to 24 deg above 3.3 ft; a
    # contact whose undercut ignored the height gave 17 and 10 (docs/bat_tracking.md, (h))
    r = outcome["results"][POOLED]
    bins = [b for b in r["plate_z_bins"]]
    assert bins[-1]["model"] - bins[0]["model"] >= 5.0
    assert r["plate_z_chi2"] <= 10.0
