"""The park table: every real export resolves, date spans pick the right park, fences."""

import glob
import math
from pathlib import Path

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.statcast import parks, read

ROOT = Path(__file__).resolve().parents[2]
EXPORTS = sorted(glob.glob(str(ROOT / "../shared/data/statcast/*.csv"))) + sorted(
    str(p) for p in (ROOT / "data").glob("statcast_*.csv"))


@pytest.mark.parametrize("path", EXPORTS, ids=lambda p: Path(p).name)
def test_every_home_team_of_a_real_export_has_a_park_and_an_elevation(path):
    df = read(path)
    df = df[df.game_year >= 2015]
    if df.empty:
        pytest.skip("no 2015-2025 rows")
    found = parks.park_of(df.home_team.to_numpy(dtype=object), df.game_date.to_numpy())
    assert all(p is not None for p in found), set(df.home_team[[p is None for p in found]])
    assert not df.elevation.isna().any()


@pytest.mark.parametrize("team, date, park", [
    ("TB", "2024-09-29", "tropicana_field"), ("TB", "2025-04-01", "steinbrenner_field"),
    ("TEX", "2019-09-29", "globe_life_park"), ("TEX", "2020-07-24", "globe_life_field"),
    ("TOR", "2020-08-11", "sahlen_field"), ("TOR", "2020-07-29", "nationals_park"),
    ("TOR", "2021-04-08", "td_ballpark"), ("TOR", "2021-06-15", "sahlen_field"),
    ("TOR", "2021-08-01", "rogers_centre"), ("ATL", "2016-06-01", "turner_field"),
    ("ATL", "2017-06-01", "truist_park"), ("OAK", "2024-06-01", "oakland_coliseum"),
    ("ATH", "2025-06-01", "sutter_health_park"), ("LAD", "2024-03-20", "gocheok_sky_dome"),
    ("LAD", "2024-03-28", "dodger_stadium"), ("AZ", "2023-05-01", "chase_field"),
    ("ARI", "2018-05-01", "chase_field"), ("XYZ", "2020-05-01", None),
])
def test_the_date_span_picks_the_park(team, date, park):
    assert parks.park_of([team], [date])[0] == park


def test_spans_of_one_team_and_kind_do_not_overlap():
    rows = parks.parks()
    for team in {p["home_team"] for p in rows}:
        for kind in ("home", "temporary"):
            spans = sorted((p["first_date"], p["last_date"]) for p in rows
                           if p["home_team"] == team and p["kind"] in ("home", "temporary"))
            assert all(a[1] < b[0] for a, b in zip(spans, spans[1:])), (team, kind)


def test_every_park_number_names_its_source():
    for p in parks.parks():
        assert not math.isnan(p["elevation_ft"]) and p["elevation_source"], p
        assert math.isnan(p["bearing_deg"]) or p["bearing_source"], p
        assert p["roof"] in ("open", "dome", "retractable"), p


def test_the_fence_at_the_lines_and_centre_matches_the_published_numbers():
    d, h = parks.fence("fenway_park", [-45.0, 0.0, 45.0])
    assert list(d) == [310.0, 390.0, 302.0]
    assert h[0] == 37.0  # the Green Monster
    d, h = parks.fence("coors_field", 0.0)
    assert d == 415.0
    d, h = parks.fence("globe_life_field", [-45.0, -22.5, 0.0, 22.5, 45.0])
    assert list(d) == [329.0, 372.0, 407.0, 374.0, 326.0] and (h == 8.0).all()


def test_the_fence_interpolates_linearly_and_holds_heights_in_steps():
    d, h = parks.fence("globe_life_field", [-33.75, 11.25])
    assert d[0] == pytest.approx((329 + 372) / 2) and d[1] == pytest.approx((407 + 374) / 2)
    d, h = parks.fence(["fenway_park", "coors_field"], [-40.0, 40.0])
    assert h[0] == 37.0 and h[1] == 17.0
    d, h = parks.fence("turner_field", [0.0])
    assert d[0] == 401.0 and np.isnan(h[0])  # no sourced height
    with pytest.raises(InputError, match="park"):
        parks.fence("nowhere", 0.0)


def test_the_yearly_elevation_still_works():
    got = parks.elevation(["COL", "ATL", "ATL", "XYZ"], [2024, 2016, 2017, 2020])
    assert list(got[:3]) == [5200.0, 939.0, 1000.0] and math.isnan(got[3])
