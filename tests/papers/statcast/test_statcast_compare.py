"""``mcbat reproduce statcast``: which real balls are compared and how, Nathan's average
spin model and its mirror for left-handed batters, the whole run on the shipped samples,
and bad input (exit 2, one line)."""

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mcbat.cli import main
from mcbat.papers.statcast.compare import CATCH_HEIGHT_FT, select_balls
from mcbat.papers.statcast.reproduce import (
    BALL,
    FLIGHTS,
    compare_file,
    read_statcast,
    reproduce,
)
from mcbat.statcast import read
from mcbat.statcast.spin import nathan_average_spin
from mcbat.statcast.weather import climate
from mcbat.study.flight import FlightSettings, flight_seasons, fly_launches

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "data"
FT, MPH, DEG, RPM = 0.3048, 0.44704, math.pi / 180, 2 * math.pi / 60


def _mcbat(capsys, *args):
    """The command line in this process: (exit code, stdout, stderr)."""
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def _strict(text):
    def refuse(name):
        raise ValueError(f"non-strict JSON constant {name}")
    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def shipped():
    return read_statcast()[0]


def test_the_sheet_case_of_the_average_spin_model():
    # BATTING.md: the calculator's published case (27.5 deg to centre field) flies with
    # 2537 rpm of backspin and 849 rpm of sidespin, the average model's numbers.
    back, side = nathan_average_spin([27.5], [0.0], ["R"])
    assert back[0] == pytest.approx(2537.0) and abs(side[0]) == pytest.approx(849.0)


def test_pulled_balls_hook_and_opposite_field_balls_slice_for_both_sides():
    # positive sidespin curves towards left field (docs/batting.md)
    back_r, side_r = nathan_average_spin([30, 30], [-30, 30], ["R", "R"])
    back_l, side_l = nathan_average_spin([30, 30], [30, -30], ["L", "L"])
    assert side_r[0] > 0 > side_r[1]  # a RHB's pull (left field) hooks left
    assert side_l[0] < 0 < side_l[1]  # a LHB's pull (right field) hooks right
    np.testing.assert_array_equal(back_l, back_r)
    np.testing.assert_array_equal(side_l, -side_r)
    with pytest.raises(ValueError, match="handedness"):
        nathan_average_spin([30], [0], ["S"])


def test_a_left_handed_ball_is_the_mirror_image_in_flight():
    la, phi = np.array([28.0, 35.0]), np.array([-20.0, 12.0])
    settings = FlightSettings()

    def land(side, spray):
        back, sideways = nathan_average_spin(la, spray, [side] * 2)
        out, status = fly_launches(settings, 0.145, 0.036, np.full(2, 100 * MPH), la * DEG,
                                   spray * DEG, back * RPM, sideways * RPM)
        assert (status == 0).all()
        return out
    right, left = land("R", phi), land("L", -phi)
    np.testing.assert_allclose(left["landing_x"], -right["landing_x"], atol=1e-9)
    np.testing.assert_allclose(left["hit_distance"], right["hit_distance"], rtol=1e-12)


def test_real_rows_get_their_comparison(shipped):
    balls = select_balls(shipped)
    events = balls["events"].astype(str)
    assert (balls.loc[events == "home_run", "comparison"] == "home_run").all()
    assert (balls.loc[events.isin(["single", "double", "triple"]), "comparison"]
            == "hit").all()
    outs = ~events.isin(["home_run", "single", "double", "triple"])
    outfield = outs & balls["hit_location"].isin([7, 8, 9])
    assert outfield.sum() > 50
    assert (balls.loc[outfield, "comparison"] == "catch").all()
    assert (balls.loc[outfield, "compare_height"] == CATCH_HEIGHT_FT).all()
    assert (balls.loc[outs & balls["hit_location"].between(1, 6), "comparison"]
            == "infield").all()
    assert (balls.loc[balls["comparison"] == "home_run", "compare_height"] == 0).all()
    # ground balls and popups are not compared; every park of the file has its elevation,
    # so every fly ball, line drive and home run with a distance is compared
    assert set(balls["bb_type"].dropna()) <= {"fly_ball", "line_drive"}
    flown = shipped["bb_type"].isin(["fly_ball", "line_drive"]) & (
        shipped["hit_distance_sc"] > 0)
    assert "PHI" in set(balls["home_team"]) and len(balls) == flown.sum()


def test_pete_alonso_home_run(shipped):
    # The 2020-09-03 file's first row: Pete Alonso's home run at Citi Field (elevation
    # 20 ft), "on a fly ball to left field", flown by each flight with its own settings.
    row = read(DATA / "statcast_2020-09-03.csv").iloc[[0]]
    assert row["events"].iloc[0] == "home_run"
    long = compare_file(row, spin_models=["nathan"])
    assert set(long["flight"]) == set(FLIGHTS)
    launch_spray = long["launch_spray_angle"].iloc[0]
    # a pulled ball hooks: it left the bat less pulled than where it came down
    assert row["spray_angle"].iloc[0] < launch_spray < 0
    back, side = nathan_average_spin([row["launch_angle"].iloc[0]], [launch_spray], ["R"])
    normal, _, _ = climate(["citi_field"], [9])
    drag = flight_seasons()[2020]["drag_scale"]["value"]
    settings = {  # what each flight means (reproduce's module docstring)
        "season": FlightSettings(elevation=20 * FT, drag_scale=drag,
                                 temperature=(normal[0] - 32) / 1.8 + 273.15),
        "published": FlightSettings(elevation=20 * FT,
                                    temperature=(normal[0] - 32) / 1.8 + 273.15),
        "standard_air": FlightSettings(elevation=20 * FT)}
    for name, flight in settings.items():
        got = long[long["flight"] == name].iloc[0]
        assert got["comparison"] == "home_run" and got["spray_angle"] < 0
        assert got["backspin"] == pytest.approx(back[0])
        assert bool(got["default"]) == (name == "season")
        out, status = fly_launches(flight, BALL.mass, BALL.radius,
                                   row["launch_speed"].to_numpy() * MPH,
                                   row["launch_angle"].to_numpy() * DEG,
                                   launch_spray * DEG, back * RPM, side * RPM)
        assert got["predicted_distance"] == pytest.approx(out["hit_distance"][0] / FT)
        assert got["residual"] == pytest.approx(got["predicted_distance"]
                                                - row["hit_distance_sc"].iloc[0])
        # a home run of this launch lands within a few tens of feet of its projection
        assert abs(got["residual"]) < 40


def test_reproduce_on_the_shipped_samples(tmp_path):
    lines = []
    paths = reproduce(tmp_path / "out", echo=lines.append)
    summary = _strict(paths["summary"].read_text())
    long = pd.read_parquet(paths["balls"])
    for column in ("launch_speed", "launch_angle", "spray_angle", "bb_type", "events",
                   "hit_distance_sc", "predicted_distance", "backspin", "sidespin",
                   "spin_model", "flight", "comparison", "residual", "default",
                   "temperature", "air_source", "drag_scale"):
        assert column in long.columns
    assert set(long["spin_model"]) == {"nathan", "inferred"}
    assert set(long["flight"]) == set(FLIGHTS)
    assert summary["balls"] * 2 * len(FLIGHTS) == len(long)
    # the default rows: one per ball, the season flight with Nathan's spin
    default = long[long["default"]]
    assert len(default) == summary["balls"]
    assert set(default["flight"]) == {"season"} and set(default["spin_model"]) == {"nathan"}
    # the summary's numbers are the parquet's residuals
    part = long[(long["spin_model"] == "nathan") & (long["flight"] == "standard_air")
                & long["comparison"].isin(["catch", "home_run", "hit"])]
    stats = summary["residuals"]["nathan"]["standard_air"]["all"]["overall"]
    r = part["residual"].dropna()
    assert stats["n"] == len(r) and stats["median"] == pytest.approx(r.median())
    assert stats["rms"] == pytest.approx(math.sqrt((r ** 2).mean()))
    # every eligible fly ball and home run of 20-50 deg is compared, and the default
    # flight brings them within 5 ft of the measured distances in the median
    season = summary["residuals"]["nathan"]["season"]
    window = season["fly_ball_and_home_run_20_to_50_deg"]
    assert season["compared_20_to_50_deg"] == season["eligible_20_to_50_deg"] == window["n"]
    assert window["n"] > 100 and abs(window["median"]) < 5.0
    by = season["fly_ball_and_home_run_20_to_50_deg_by"]
    assert set(by["season"]) == {"2019", "2020"} and set(by["month"]) == {"07", "09"}
    assert sum(v["n"] for v in by["temperature"].values()) == window["n"]
    # the inferred spin: every compared ball but a few got one and sidespin's sign
    # agrees with the average model's where the ball was pulled or hit the other way
    inferred = long[(long["spin_model"] == "inferred") & (long["flight"] == "standard_air")]
    assert np.isfinite(inferred["backspin"]).mean() > 0.95
    wide = (inferred["spray_angle"].abs() > 25) & np.isfinite(inferred["sidespin"])
    nathan_side = part.set_index("ball")["sidespin"]
    agree = np.sign(inferred.loc[wide, "sidespin"].to_numpy()) == np.sign(
        nathan_side.reindex(inferred.loc[wide, "ball"]).to_numpy())
    assert wide.sum() > 20 and agree.mean() > 0.8
    for name in ("predicted_vs_measured.png", "residual_vs_launch_angle.png",
                 "residual_by_season_month_temperature.png"):
        assert (tmp_path / "out" / "figures" / name).read_bytes()[:4] == b"\x89PNG"
    assert any("FB+HR 20-50" in line for line in lines)


def test_a_weather_table_sets_each_game_air(tmp_path):
    # the shipped Retrosheet sample covers the 2020-09-03 games: their balls fly in their
    # game's recorded temperature, the 2019 file's in the climate (or indoors)
    paths = reproduce(tmp_path / "out", weather_path=DATA / "retrosheet_weather_sample.csv",
                      echo=lambda *_: None)
    long = pd.read_parquet(paths["balls"])
    default = long[long["default"]]
    of_2020 = default[default["game_year"] == 2020]
    assert set(of_2020["air_source"]) <= {"weather", "indoor"}
    assert (of_2020["air_source"] == "weather").mean() > 0.7
    assert set(default.loc[default["game_year"] == 2019, "air_source"]) <= {"climate",
                                                                           "indoor"}


def test_cli_on_a_file_subset(tmp_path, capsys):
    # one game of the 2019 file through the command line
    lines = (DATA / "statcast_2019_darvish.csv").read_text(encoding="utf-8-sig").splitlines()
    head = lines[0]
    game = [line for line in lines[1:] if '"2019-07-30"' in line or "2019-07-30" in line]
    path = tmp_path / "game.csv"
    path.write_text("\n".join([head, *game]) + "\n", encoding="utf-8")
    code, out, err = _mcbat(capsys, "reproduce", "statcast", "--data", str(path), "--out",
                            str(tmp_path / "o"))
    assert code == 0, err
    summary = _strict((tmp_path / "o" / "summary.json").read_text())
    assert summary["data"] == str(path) and 0 < summary["balls"] < 40
    assert "spin model 'nathan'" in out


@pytest.mark.parametrize("content, field", [
    ("a,b\n1,2\n", "missing"),
    (None, "hit_distance_sc"),
])
def test_bad_files_exit_2_with_one_line(tmp_path, capsys, content, field):
    path = tmp_path / "bad.csv"
    if content is None:  # a real export without a fly ball, line drive or home run
        path.write_bytes((DATA / "statcast_2014_jeter.csv").read_bytes())
    else:
        path.write_text(content)
    for args in (("reproduce", "statcast", "--data", str(path), "--out",
                  str(tmp_path / "o")), ("fit", "--flight", "--data", str(path))):
        code, _, err = _mcbat(capsys, *args)
        assert code == 2, err
        assert len(err.strip().splitlines()) == 1 and field in err
        assert "Traceback" not in err
    assert not (tmp_path / "o").exists()  # nothing written
