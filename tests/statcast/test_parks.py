"""The park table: every real export resolves, date spans pick the right park, fences."""

import csv
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


# --- neutral sites ---------------------------------------------------------------------

NEUTRAL_SERIES = [  # (park, first day, last day, the two clubs)
    ("estadio_monterrey", "2018-05-04", "2018-05-06", ("SD", "LAD")),
    ("estadio_monterrey", "2019-04-13", "2019-04-14", ("CIN", "STL")),
    ("estadio_monterrey", "2019-05-04", "2019-05-05", ("HOU", "LAA")),
    ("estadio_alfredo_harp_helu", "2023-04-29", "2023-04-30", ("SD", "SF")),
    ("estadio_alfredo_harp_helu", "2024-04-27", "2024-04-28", ("HOU", "COL")),
    ("london_stadium", "2019-06-29", "2019-06-30", ("BOS", "NYY")),
    ("london_stadium", "2023-06-24", "2023-06-25", ("STL", "CHC")),
    ("tokyo_dome", "2019-03-20", "2019-03-21", ("OAK", "SEA")),
    ("tokyo_dome", "2025-03-18", "2025-03-19", ("CHC", "LAD")),
    ("field_of_dreams", "2021-08-12", "2021-08-12", ("CWS", "NYY")),
    ("field_of_dreams", "2022-08-11", "2022-08-11", ("CHC", "CIN")),
    ("rickwood_field", "2024-06-20", "2024-06-20", ("STL", "SF")),
    ("bowman_field", "2017-08-20", "2017-08-20", ("PIT", "STL")),
    ("bowman_field", "2018-08-19", "2018-08-19", ("PHI", "NYM")),
    ("bowman_field", "2019-08-18", "2019-08-18", ("PIT", "CHC")),
    ("bowman_field", "2021-08-22", "2021-08-22", ("CLE", "LAA")),
    ("bowman_field", "2022-08-21", "2022-08-21", ("BAL", "BOS")),
    ("bowman_field", "2023-08-20", "2023-08-20", ("WSH", "PHI")),
    ("bowman_field", "2024-08-18", "2024-08-18", ("DET", "NYY")),
    ("bowman_field", "2025-08-17", "2025-08-17", ("NYM", "SEA")),
    ("fort_bragg_field", "2016-07-03", "2016-07-03", ("ATL", "MIA")),
    ("hiram_bithorn_stadium", "2018-04-17", "2018-04-18", ("MIN", "CLE")),
    ("bristol_motor_speedway", "2025-08-02", "2025-08-03", ("CIN", "ATL")),
    ("gocheok_sky_dome", "2024-03-20", "2024-03-21", ("LAD", "SD")),
]


@pytest.mark.parametrize("park, first, last, teams", NEUTRAL_SERIES,
                         ids=[f"{s[0]}-{s[1]}" for s in NEUTRAL_SERIES])
def test_a_neutral_series_takes_both_clubs_to_its_park_and_only_on_its_dates(
        park, first, last, teams):
    days = np.arange(np.datetime64(first), np.datetime64(last) + 1)
    for team in teams:
        assert list(parks.park_of([team] * len(days), days)) == [park] * len(days)
        around = [np.datetime64(first) - 1, np.datetime64(last) + 1]
        got = parks.park_of([team, team], around)
        assert all(p is not None and p != park for p in got), (team, got)


def test_mexico_city_is_a_mile_and_a_half_up_and_the_padres_are_home_the_next_day():
    got = parks.elevation(["SD", "SD", "SD"],
                          game_date=["2023-04-29", "2023-04-30", "2023-05-01"])
    assert got[0] > 7000 and got[1] > 7000
    assert parks.park_of(["SD"], ["2023-05-01"])[0] == "petco_park"
    assert got[2] == parks.park_value(["petco_park"], "elevation_ft")[0] < 100


def test_a_neutral_row_wins_over_a_temporary_and_a_home_park():
    # the Athletics' Tokyo games of 2019 are not at the Coliseum
    assert parks.park_of(["OAK", "OAK"], ["2019-03-21", "2019-03-28"]).tolist() == [
        "tokyo_dome", "oakland_coliseum"]
    # every neutral row sorts ahead of every temporary and home row
    kinds = [p["kind"] for p in parks.parks()]
    order = {"neutral": 0, "temporary": 1, "home": 2}
    assert [order[k] for k in kinds] == sorted(order[k] for k in kinds)


# --- sources -------------------------------------------------------------------------

# parks whose elevation has no sourced number yet (each an "assumed: ..." source)
UNSOURCED_ELEVATIONS = {
    "citizens_bank_park", "petco_park", "nationals_park", "steinbrenner_field",
    "globe_life_park", "sahlen_field", "td_ballpark", "gocheok_sky_dome",
    "london_stadium", "tokyo_dome", "fort_bragg_field", "hiram_bithorn_stadium",
}


def test_every_elevation_is_sourced_but_for_the_listed_parks():
    assumed = {p["park_id"] for p in parks.parks()
               if p["elevation_source"].startswith("assumed")}
    assert assumed == UNSOURCED_ELEVATIONS
    for p in parks.parks():
        assert p["elevation_source"] and not math.isnan(p["elevation_ft"]), p


def test_every_fence_source_key_is_defined_in_the_data_readme():
    readme = (ROOT / "data" / "README.md").read_text(encoding="utf-8")
    text = (ROOT / "data" / "park_fences.csv").read_text(encoding="utf-8")
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    keys = {cell.split()[0] for row in rows
            for cell in (row["distance_source"], row["height_source"]) if cell.strip()}
    missing = {k for k in keys if f"`{k}" not in readme}
    assert not missing, missing


# --- fence configurations ------------------------------------------------------------

def test_the_configurations_of_a_park_do_not_overlap():
    by_park: dict = {}
    for c in parks.fence_configurations():
        assert c["first_date"] <= c["last_date"], c["config_id"]
        by_park.setdefault(c["park_id"], []).append((c["first_date"], c["last_date"]))
    for park, spans in by_park.items():
        spans.sort()
        assert all(a[1] < b[0] for a, b in zip(spans, spans[1:])), park


@pytest.mark.parametrize("park, spray, before, after, dist_before, dist_after", [
    ("comerica_park", 0.0, "2022-10-05", "2023-04-06", 420.0, 412.0),
    ("minute_maid_park", 0.0, "2016-09-28", "2017-04-03", 435.0, 409.0),  # Tal's Hill
    ("loandepot_park", 0.0, "2015-10-04", "2016-04-05", 422.0, 407.0),
    ("loandepot_park", 0.0, "2019-09-29", "2020-07-24", 407.0, 400.0),
    ("london_stadium", 0.0, "2019-06-29", "2023-06-24", 385.0, 392.0),
])
def test_a_fence_change_picks_the_configuration_of_the_date(
        park, spray, before, after, dist_before, dist_after):
    d, _ = parks.fence(park, [spray, spray], game_date=[before, after])
    assert list(d) == [dist_before, dist_after]


def test_camden_yards_left_field_moved_back_in_2022_and_half_way_in_again_in_2025():
    d = parks.fence("camden_yards", [-22.6] * 4,
                    game_date=["2021-09-30", "2022-04-08", "2024-09-29", "2025-03-31"])[0]
    assert d[1] - d[0] > 15  # the 2022 outline's wall, about 25 ft back
    assert d[1] == d[2] and d[3] == pytest.approx((d[0] + d[1]) / 2, abs=0.2)
    d = parks.fence("camden_yards", [10.0] * 2, game_date=["2021-06-01", "2023-06-01"])[0]
    assert d[0] == d[1]  # right field did not move


def test_fence_heights_follow_the_date_too():
    _, h = parks.fence("camden_yards", [-40.0] * 3,
                       game_date=["2021-06-01", "2023-06-01", "2025-06-01"])
    assert list(h) == [7.0, 13.0, 7.0]
    _, h = parks.fence("comerica_park", [0.0, 0.0], game_date=["2022-06-01", "2023-06-01"])
    assert list(h) == [8.0, 7.0]


def test_without_a_date_a_park_means_its_fences_of_now_and_config_ids_are_accepted():
    d_now, _ = parks.fence("camden_yards", -22.6)
    d_2025, _ = parks.fence("camden_yards", -22.6, game_date="2025-06-01")
    d_2021, _ = parks.fence("camden_yards", -22.6, game_date="2021-06-01")
    d_2023, _ = parks.fence("camden_yards", -22.6, game_date="2023-06-01")
    assert d_now == d_2025 != d_2021
    ids = parks.fence_config(["camden_yards"] * 2 + ["fenway_park", "nowhere"],
                             ["2021-06-01", "2023-06-01", "2023-06-01", "2023-06-01"])
    assert list(ids) == ["camden_yards@opening", "camden_yards@2022-01-01",
                         "fenway_park@opening", None]
    d, h = parks.fence(ids, [-22.6, -22.6, -45.0, 0.0])
    assert list(d[:3]) == [d_2021, d_2023, 310.0] and h[2] == 37.0 and np.isnan(d[3])


def test_a_missing_date_or_a_park_without_fences_gives_nan():
    d, h = parks.fence(["fenway_park", "fenway_park", "rickwood_field"], [0.0, 0.0, 0.0],
                       game_date=["2020-06-01", "not a date", "2024-06-20"])
    assert d[0] == 390.0 and np.isnan(d[1]) and np.isnan(d[2]) and np.isnan(h[2])


# --- the dense outline ------------------------------------------------------------------

def test_every_outlined_park_has_its_wall_every_few_degrees():
    for c in parks.fence_configurations():
        sources = c["config_id"]
        a = c["spray_angle_deg"]
        if len(a) <= 5:  # a park without an outline keeps its published points
            continue
        assert len(a) >= 30, sources
        assert np.all(np.diff(a) > 0) and a[0] == -45.0 and a[-1] == 45.0, sources
        inner = a[(a >= -40) & (a <= 40)]
        assert np.diff(inner).max() < 4.0, sources


def test_fenways_wall_follows_its_published_turns():
    # Published: 310 ft at the pole, 379 ft in left-centre, 390 ft in centre, 420 ft at the
    # triangle, 380 ft in right field, 302 ft at the pole (the sparse table cut 15-35 ft
    # inside between them). The outline's angles are its own, the distances checked here.
    a, d, h = parks.fences()["fenway_park"]
    lcf = (a > -12) & (a < -5)
    assert 376 <= d[lcf].max() <= 388 and (h[a < -10] == 37.0).all()
    assert abs(d[(a > 5) & (a < 15)].max() - 420) <= 5
    assert abs(np.median(d[(a > 18) & (a < 38)]) - 380) <= 5
    dist, _ = parks.fence("fenway_park", [-25.0, 25.0])
    assert dist[0] > 325 and dist[1] > 370


def test_the_outline_is_scaled_to_the_published_centre_field():
    for pid in ("yankee_stadium", "comerica_park", "fenway_park", "tropicana_field"):
        a, d, _ = parks.fences()[pid]
        near = (np.abs(a) < 2.5) & (a != 0.0)
        assert near.any(), pid
        assert np.abs(d[near] - d[a == 0.0][0]).max() < 6, pid
