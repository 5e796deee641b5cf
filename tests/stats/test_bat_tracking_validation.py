"""``python -m validation bat_tracking``: studies/bat_tracking.toml's contact fitted to the
tracked balls in play of two 2024 exports and judged on a 2025 export it never saw."""

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT.parent / "shared" / "data" / "statcast"
FIT = ["statcast_2024_skubal.csv", "statcast_2024_ohtani.csv"]
JUDGE = ["statcast_2025-05-01.csv"]

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not all((DATA / f).exists() for f in FIT + JUDGE),
                                 reason="the shared Statcast exports are absent")]


@pytest.fixture(scope="module")
def outcome():
    sys.path.insert(0, str(ROOT))
    from validation.bat_tracking import run

    # The bat-speed error's scan (step 1) chose 0 mph on these files; it is passed here
    # so that the test runs one fit.
    return run(FIT, JUDGE, samples=100000, seed=2025,
               errors={"attack_angle": 0.0, "bat_speed": 0.0})


def _judged(outcome):
    return outcome["results"][("out of sample", JUDGE[0])]


def test_out_of_sample_distributions(outcome):
    r = _judged(outcome)
    assert r["ks_launch_speed"] <= 0.05
    assert r["ks_launch_angle"] <= 0.05


def test_out_of_sample_launch_speed_calibrated(outcome):
    r = _judged(outcome)
    assert 0.07 <= r["launch_speed_above_p90"] <= 0.13
    assert 0.07 <= r["launch_speed_below_p10"] <= 0.13


@pytest.mark.xfail(strict=True, reason="the launch angle's upper tail: 13.6 % of the 2025 "
                   "rows lie above their 90th percentile (docs/bat_tracking.md)")
def test_out_of_sample_launch_angle_calibrated(outcome):
    r = _judged(outcome)
    assert 0.07 <= r["launch_angle_above_p90"] <= 0.13
    assert 0.07 <= r["launch_angle_below_p10"] <= 0.13


@pytest.mark.xfail(strict=True, reason="the 65-70 mph bin of the 2025 rows: measured 89.0, "
                   "model 86.1 mph (docs/bat_tracking.md)")
def test_out_of_sample_bat_speed_bins(outcome):
    for b in _judged(outcome)["bat_speed_bins"]:
        if b["rows"] >= 100:
            assert abs(b["model"] - b["measured"]) <= 2.0, b
