"""``mcbat replay``: a real day's batted balls flown again at other parks, temperatures,
winds and drags; CSV and Parquet out with units; bad conditions refused in one line."""

from pathlib import Path

import numpy as np
import pytest

from mcbat.cli import main
from mcbat.dataset.tables import read_table
from mcbat.errors import InputError
from mcbat.statcast import read
from mcbat.statcast.replay import Conditions, replay, replay_summary

DATA = Path(__file__).resolve().parents[2] / "data" / "statcast_2020-09-03.csv"


@pytest.fixture(scope="module")
def day():
    return read(DATA)


def test_as_it_was_is_no_change(day):
    out = replay(day)
    assert len(out) > 300
    assert np.nanmax(np.abs(out["change"])) == 0.0
    assert (out["park"] == out["actual_park"]).all()
    assert out.attrs["units"]["predicted_distance"] == "ft"


def test_coors_field_carries_farther_than_miami(day):
    coors = replay_summary(replay(day, Conditions(park="COL")))
    miami = replay_summary(replay(day, Conditions(park="MIA")))
    assert coors["median_distance_ft"] - miami["median_distance_ft"] >= 15.0
    assert coors["home_runs"] >= miami["home_runs"]


def test_a_hot_day_carries_farther_than_a_cold_one(day):
    hot = replay(day, Conditions(park="NYY", temperature=95.0))
    cold = replay(day, Conditions(park="NYY", temperature=45.0))
    window = (hot["launch_angle"].between(20, 50)
              & ((hot["bb_type"] == "fly_ball") | (hot["events"] == "home_run")))
    gain = (hot["predicted_distance"] - cold["predicted_distance"])[window]
    assert gain.median() >= 5.0 and (gain > 0).all()


def test_a_dome_ignores_the_wind_and_an_open_park_does_not(day):
    calm_dome = replay(day, Conditions(park="TB"))
    windy_dome = replay(day, Conditions(park="TB", wind_speed=20.0, wind_direction="tocf"))
    np.testing.assert_array_equal(calm_dome["predicted_distance"],
                                  windy_dome["predicted_distance"])
    calm = replay(day, Conditions(park="CHC", temperature=75.0))
    out_to_cf = replay(day, Conditions(park="CHC", temperature=75.0, wind_speed=15.0,
                                       wind_direction="tocf"))
    window = calm["launch_angle"].between(20, 50) & (calm["bb_type"] == "fly_ball")
    gain = (out_to_cf["predicted_distance"] - calm["predicted_distance"])[window]
    assert gain.median() > 10.0


def test_less_drag_carries_farther(day):
    base = replay(day, Conditions(drag_scale=1.0))
    less = replay(day, Conditions(drag_scale=0.9))
    assert (less["predicted_distance"] > base["predicted_distance"]).mean() > 0.95


@pytest.mark.parametrize("kw, field", [
    ({"park": "XYZ"}, "park"), ({"temperature": 500.0}, "temperature"),
    ({"wind_speed": 10.0}, "wind_direction"),
    ({"wind_speed": 10.0, "wind_direction": "sideways"}, "wind_direction"),
    ({"drag_scale": 0.0}, "drag_scale")])
def test_bad_conditions_name_their_field(kw, field):
    with pytest.raises(InputError) as err:
        Conditions(**kw)
    assert err.value.field == field


def test_the_command_writes_csv_with_units_and_parquet(tmp_path, capsys):
    csv = tmp_path / "coors.csv"
    assert main(["replay", str(DATA), "--park", "COL", "--out", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "replayed at COL" in out and "median change" in out
    assert "launch_speed [mph]" in csv.read_text().splitlines()[0]
    table = read_table(csv)
    assert table.attrs["units"]["predicted_distance"] == "ft"
    assert "predicted_distance" in table.columns and len(table) > 300
    parquet = tmp_path / "coors.parquet"
    assert main(["replay", str(DATA), "--park", "COL", "--out", str(parquet),
                 "--json"]) == 0
    again = read_table(parquet)
    np.testing.assert_allclose(again["predicted_distance"], table["predicted_distance"])


@pytest.mark.parametrize("args, flag", [
    (["--park", "XYZ"], "--park"), (["--wind", "10"], "--wind-dir"),
    (["--out", "x.txt"], "--out")])
def test_bad_flags_exit_2_with_one_line(capsys, args, flag):
    assert main(["replay", str(DATA), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and flag in err
