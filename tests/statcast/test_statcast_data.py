"""The shipped Statcast rows and the park table: the bytes recorded in data/README.md, the
layouts they are said to have, and a park table that covers every current team."""

import csv
import hashlib
import math
from importlib import resources

import pytest

from mcbat.statcast import parks

SHIPPED = {
    "statcast_2019_darvish.csv":
        "d0cfd3ccce05037e67bf31a8dcf99e1c9fa02baa71c9d8ad8a74dc02493e415d",
    "statcast_2020-09-03.csv":
        "5bef7b0e41660c36b529577f79a6d943b89a8847ea45b79ffab5430fbeb426e1",
    "statcast_2014_jeter.csv":
        "8e1f6bed44fca7455a366dc6e1d26b993adfb63e492fd80d4f81bd5a868dd6b2",
}
# The 30 franchises by the code Savant writes for their home games in the latest season.
CURRENT = {"AZ", "ATL", "BAL", "BOS", "CHC", "CWS", "CIN", "CLE", "COL", "DET", "HOU", "KC",
           "LAA", "LAD", "MIA", "MIL", "MIN", "NYM", "NYY", "ATH", "PHI", "PIT", "SD", "SEA",
           "SF", "STL", "TB", "TEX", "TOR", "WSH"}


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_shipped_exports_are_the_bytes_recorded_in_the_provenance(name):
    data = resources.files("mcbat.data").joinpath(name).read_bytes()
    assert hashlib.sha256(data).hexdigest() == SHIPPED[name]


def _header(name):
    text = resources.files("mcbat.data").joinpath(name).read_text(encoding="utf-8-sig")
    return next(csv.reader(text.splitlines()))


def test_the_shipped_exports_have_two_column_layouts():
    old, new = _header("statcast_2020-09-03.csv"), _header("statcast_2014_jeter.csv")
    assert _header("statcast_2019_darvish.csv") == old
    assert len(old) == 89 and len(new) == 92
    assert "spin_axis" not in old and "spin_axis" in new
    assert set(new) - set(old) == {"spin_axis", "delta_home_win_exp", "delta_run_exp"}


def test_every_current_team_has_a_park_this_season():
    rows = [p for p in parks.parks() if p["kind"] != "neutral"]
    current = {p["home_team"] for p in rows if p["last_season"] >= 2025}
    assert CURRENT <= current
    # one park per team and date: no overlapping spans (neutral-site dates aside)
    for team in {p["home_team"] for p in rows}:
        spans = sorted((p["first_date"], p["last_date"]) for p in rows
                       if p["home_team"] == team)
        assert all(a[1] < b[0] for a, b in zip(spans, spans[1:])), team


def test_every_elevation_names_its_source_and_coors_is_a_mile_up():
    for park in parks.parks():
        assert math.isnan(park["elevation_ft"]) or park["source"], park
        assert not park["source"] or not math.isnan(park["elevation_ft"]), park
    assert parks.elevation(["COL"], [2024])[0] == 5200.0
    highest = max((p for p in parks.parks()
                   if p["kind"] != "neutral" and not math.isnan(p["elevation_ft"])),
                  key=lambda p: p["elevation_ft"])  # Mexico City (neutral) is higher
    assert highest["park"] == "Coors Field"


def test_elevation_follows_the_season_and_unknowns_are_nan():
    teams = ["ATL", "ATL", "TOR", "TOR", "OAK", "XYZ", "COL"]
    years = [2016, 2017, 2019, 2021, 2025, 2020, float("nan")]
    got = parks.elevation(teams, years)
    assert got[0] == 939.0 and got[1] == 1000.0 and got[2] == 249.0
    assert got[3] == 600.0 and got[4] == 20.0  # 1 July: Buffalo in 2021, Sacramento in 2025
    assert all(math.isnan(v) for v in got[5:])  # unknown team, no year
