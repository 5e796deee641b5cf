"""The air of a row: weather over climate, roofs, wind conventions, weather-file errors."""

import math

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.statcast import weather

MPH = 0.44704


@pytest.mark.parametrize("code, ux, uy", [
    ("tocf", 0, 1), ("fromcf", 0, -1), ("ltor", 1, 0), ("rtol", -1, 0),
    ("tolf", -math.sqrt(0.5), math.sqrt(0.5)), ("torf", math.sqrt(0.5), math.sqrt(0.5)),
    ("fromlf", math.sqrt(0.5), -math.sqrt(0.5)), ("fromrf", -math.sqrt(0.5), -math.sqrt(0.5)),
])
def test_each_wind_code_points_its_way_at_its_speed(code, ux, uy):
    x, y = weather.wind_vector(code, 10.0)
    assert x == pytest.approx(10 * MPH * ux) and y == pytest.approx(10 * MPH * uy)
    assert math.hypot(x, y) == pytest.approx(4.4704)


def test_unknown_wind_is_no_wind_and_a_bad_code_is_an_error():
    x, y = weather.wind_vector(["unknown", "", "tocf", "tocf"], [10, 10, -1, np.nan])
    assert (x == 0).all() and (y == 0).all()
    with pytest.raises(InputError, match="wind_direction"):
        weather.wind_vector("sideways", 5)


def _table():
    return pd.DataFrame({"game_pk": [1, 2, 3, 4], "home_team": ["BOS", "TB", "HOU", "BOS"],
                         "game_date": pd.to_datetime(["2021-07-01"] * 3 + ["2021-07-02"]),
                         "game_year": [2021] * 4})


def _weather(tmp_path, text):
    path = tmp_path / "w.csv"
    path.write_text("game_pk,temperature,wind_speed,wind_direction,roof\n" + text)
    return path


def test_a_weather_row_wins_and_a_closed_roof_or_dome_is_indoor_air(tmp_path):
    path = _weather(tmp_path, "1,85,10,tocf,\n2,95,12,tocf,open\n3,91,8,ltor,closed\n")
    got = weather.air(_table(), path)
    bos = got.iloc[0]
    assert bos.air_source == "weather" and bos.temperature == 85.0
    assert bos.wind_y == pytest.approx(10 * MPH) and bos.wind_source == "weather"
    for row in (got.iloc[1], got.iloc[2]):  # Tropicana's dome; Houston's roof closed
        assert row.roof_closed and row.air_source == "indoor"
        assert row.temperature == weather.INDOOR_TEMPERATURE
        assert row.wind_x == 0 and row.wind_y == 0 and row.wind_source == "indoor"
    other = got.iloc[3]  # no weather row: Fenway's normal July game
    normal, _, _ = weather.climate(["fenway_park"], [7])
    assert other.air_source == "climate" and other.temperature == normal[0]
    assert 70.0 < other.temperature < 90.0
    assert other.pressure == 29.92 and other.wind_source == "none"
    assert got.attrs["units"]["wind_x"] == "m/s"


def test_a_climate_row_is_used_when_no_weather_row(monkeypatch):
    monkeypatch.setattr(weather, "_climate_rows",
                        lambda: {("fenway_park", 7): (77.0, 60.0, 0.0)})
    got = weather.air(_table())
    assert got.iloc[0].air_source == "climate" and got.iloc[0].temperature == 77.0
    assert got.iloc[0].relative_humidity == 60.0
    assert got.iloc[2].air_source == "indoor"  # Houston's roof: no climate row, closed


def test_a_retractable_roof_of_unknown_state_is_as_it_usually_was(monkeypatch):
    table = pd.DataFrame({"game_pk": [1, 2], "home_team": ["SEA", "HOU"],
                          "game_date": pd.to_datetime(["2021-07-01"] * 2)})
    monkeypatch.setattr(weather, "_climate_rows",
                        lambda: {("t_mobile_park", 7): (73.0, float("nan"), 0.1),
                                 ("minute_maid_park", 7): (73.0, float("nan"), 0.9)})
    got = weather.air(table)
    assert got.iloc[0].air_source == "climate" and got.iloc[0].temperature == 73.0
    assert not got.iloc[0].roof_closed
    assert got.iloc[1].air_source == "indoor" and got.iloc[1].roof_closed


def test_doubleheaders_match_by_game_pk_order(tmp_path):
    table = pd.DataFrame({"game_pk": [20, 10], "home_team": ["BOS", "BOS"],
                          "game_date": pd.to_datetime(["2021-07-01"] * 2)})
    path = tmp_path / "w.csv"
    path.write_text("game_date,home_team,game_number,temperature,wind_speed,"
                    "wind_direction,roof\n2021-07-01,BOS,1,60,0,,\n2021-07-01,BOS,2,70,0,,\n")
    got = weather.air(table, path)
    assert list(got.temperature) == [70.0, 60.0]


@pytest.mark.parametrize("row, column", [
    ("1,500,10,tocf,", "temperature"), ("1,80,10,sideways,", "wind_direction"),
    ("1,80,10,tocf,half", "roof"), ("x,80,10,tocf,", "game_pk"), ("1,80,400,tocf,", "wind_speed"),
])
def test_a_bad_cell_names_its_column_and_line(tmp_path, row, column):
    with pytest.raises(InputError) as err:
        weather.read_weather(_weather(tmp_path, "2,70,5,tolf,\n" + row + "\n"))
    assert f"{column}: line 3" in str(err.value)


def test_a_game_twice_is_an_error_and_retrosheet_unknowns_are_nan(tmp_path):
    with pytest.raises(InputError, match="game_pk: line 3: the same game twice"):
        weather.read_weather(_weather(tmp_path, "1,70,5,tolf,\n1,71,5,tolf,\n"))
    got = weather.read_weather(_weather(tmp_path, "1,0,-1,unknown,closed\n"))
    assert np.isnan(got.temperature[0]) and np.isnan(got.wind_speed[0])
    assert got.attrs["units"]["temperature"] == "degF"
