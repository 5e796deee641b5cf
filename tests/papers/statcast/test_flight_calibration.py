"""``mcbat fit --flight``: the flight model's drag and lift scales fitted to measured
distances; injection on synthetic distances from known scales; the calibrated preset."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mcbat.api import flight_case_from_dict, solve_flight
from mcbat.cli import main
from mcbat.errors import InputError
from mcbat.papers.statcast.calibrate import (
    FIT_CLASSES,
    fit_scales,
    flight_table,
    predict,
)
from mcbat.papers.statcast.compare import select_balls
from mcbat.papers.statcast.reproduce import balls_in_their_air, read_statcast
from mcbat.statcast.spin import nathan_average_spin
from mcbat.stats.fit.estimate import Likelihood
from mcbat.stats.models.flight import FlightFitSetup
from mcbat.study.flight import (
    FLIGHT_PRESETS,
    flight_seasons,
    parse_flight,
    season_wind_scale,
)

PRESET = "statcast_2025"
SHARED_2025 = Path(__file__).resolve().parents[3].parent / "shared" / "data" / "statcast" / \
    "statcast_2025-05-01.csv"


@pytest.fixture(scope="module")
def launches():
    """The real launches of the calibration sample as a flight table."""
    balls = select_balls(read_statcast()[0])
    balls = balls[balls["comparison"].isin(FIT_CLASSES)].reset_index(drop=True)
    back, side = nathan_average_spin(balls["launch_angle"], balls["spray_angle"],
                                     balls["handedness"])
    table = flight_table(balls, back, side, 1.0)
    return table[np.isfinite(predict(FlightFitSetup(), table))].reset_index(drop=True)


def _inject(launches, truth, sigma, rng, rows=None):
    table = launches if rows is None else launches.iloc[:rows].reset_index(drop=True)
    table = table.copy()
    table["hit_distance_sc"] = (predict(FlightFitSetup(), table, truth)
                                + sigma * rng.standard_normal(len(table)))
    return table


def test_every_season_preset_is_its_table_row():
    seasons = flight_seasons()
    assert set(range(2015, 2026)) <= set(seasons)
    for season, row in seasons.items():
        preset = FLIGHT_PRESETS[f"statcast_{season}"]
        assert preset["drag_scale"] == row["drag_scale"] and preset["model"] == "nathan"
        assert 0.8 < row["drag_scale"]["value"] < 1.2 and row["drag_scale"]["error"] > 0
        assert row["balls"] >= 40 and row["ball"] == "regulation"
    # the ball is deader since 2022 than in 2019-2020 (more drag), beyond the errors
    later = seasons[2024]["drag_scale"]
    earlier = seasons[2019]["drag_scale"]
    assert later["value"] - earlier["value"] > 3 * math.hypot(later["error"],
                                                               earlier["error"])


@pytest.mark.skipif(not SHARED_2025.exists(), reason="the shared 2025 export is absent")
def test_the_2025_row_refits_from_its_file():
    # the 2025 row rests on one real export: refitting it gives the table's value
    from validation.flight_seasons import fit_season, read_files

    balls = balls_in_their_air(read_files([SHARED_2025]))
    balls["wind_x"] *= season_wind_scale()
    balls["wind_y"] *= season_wind_scale()
    cal = fit_season(balls, ("drag_scale",), "2025")
    row = flight_seasons()[2025]
    assert cal.balls == row["balls"]
    assert cal.result.params["drag_scale"] == pytest.approx(row["drag_scale"]["value"],
                                                            abs=1e-4)


def test_injected_scales_are_recovered(launches):
    # nearly noiseless distances: the fit finds the truth to well within its small error
    truth = {"drag_scale": 0.85, "lift_scale": 1.3}
    table = _inject(launches, truth, 0.5, np.random.default_rng(3))
    cal = fit_scales(table)
    for name, value in truth.items():
        iv = cal.result.intervals[name]
        assert abs(cal.result.params[name] - value) < 3 * max(iv["lower_error"],
                                                              iv["upper_error"])
        assert iv["upper_error"] < 0.01
    assert cal.sigma == pytest.approx(0.5, rel=0.2)


def test_intervals_have_the_width_of_the_scatter_of_the_fits(launches):
    # Reduced coverage check (the full one: validation/flight_calibration_coverage.py,
    # 200 tables): on 10 tables of 40 balls the pulls (fit - truth) / error are centred
    # and of unit width, within what 10 tables can tell.
    truth = {"drag_scale": 0.9, "lift_scale": 1.2}
    rng = np.random.default_rng(11)
    pulls = {name: [] for name in truth}
    for _ in range(10):
        cal = fit_scales(_inject(launches, truth, 15.0, rng, rows=40))
        for name, value in truth.items():
            iv = cal.result.intervals[name]
            fitted = cal.result.params[name]
            pulls[name].append((fitted - value)
                               / (iv["upper_error"] if fitted < value else iv["lower_error"]))
    for name, p in pulls.items():
        p = np.array(p)
        assert abs(p.mean()) < 0.9 and 0.5 < p.std(ddof=1) < 1.6, (name, p)


def test_the_likelihood_needs_the_scatter_column(launches):
    table = launches.drop(columns="hit_distance_sc_err")
    with pytest.raises(InputError, match="hit_distance_sc_err"):
        Likelihood(FlightFitSetup(), table, ("drag_scale",))


def test_one_free_scale_and_bad_free(capsys):
    assert main(["fit", "--flight", "--free", "lift_scale", "--intervals", "curvature"]) == 0
    out = capsys.readouterr().out
    assert "lift_scale" in out and "drag_scale" not in out
    assert main(["fit", "--flight", "--free", "e,mu"]) == 2
    err = capsys.readouterr().err
    assert "--free" in err and len(err.strip().splitlines()) == 1
    assert main(["fit", "--flight", "--spin-model", "guessed"]) == 2
    assert "--spin-model" in capsys.readouterr().err


def test_the_preset_in_flight_settings_and_mcbat_flight():
    settings = parse_flight({"preset": PRESET})
    assert settings.drag_scale == FLIGHT_PRESETS[PRESET]["drag_scale"]["value"]
    assert settings.lift_scale == FLIGHT_PRESETS[PRESET]["lift_scale"]["value"]
    assert settings.config()["preset"] == PRESET
    for bad in ({"preset": PRESET, "drag_scale": 1.0}, {"preset": PRESET, "model": "nathan"},
                {"preset": "coors1995"}):
        with pytest.raises(InputError) as err:
            parse_flight(bad)
        assert err.value.field in ("flight.drag_scale", "flight.model", "flight.preset")
    ball = {"launch_speed": 103, "launch_angle": 27, "backspin": 2000}  # mph, deg, rpm
    default = solve_flight(flight_case_from_dict(ball)).hit_distance
    calibrated = solve_flight(flight_case_from_dict({**ball, "preset": PRESET})).hit_distance
    assert calibrated < default  # the 2025 ball: more drag than the published model


def test_fit_without_a_study_or_flight_exits_2(capsys):
    assert main(["fit", "--data", "table.csv"]) == 2
    err = capsys.readouterr().err
    assert "--study" in err and "--flight" in err
    assert main(["fit", "--study", "s.toml", "--data", "t.csv", "--spin-model", "nathan"]) == 2
    assert "--spin-model" in capsys.readouterr().err


def test_the_fit_reports_its_residuals_in_sample_and_held_out(capsys):
    assert main(["fit", "--flight", "--free", "drag_scale", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    held = out["holdout"]
    assert held["split"] == "alternate games"
    assert held["in_sample"]["n"] == held["out_of_sample"]["n"] > 50
    # the held-out balls are predicted by fits to the other games: on this many balls the
    # drag transfers, and their residuals are centred within a few feet
    assert abs(held["out_of_sample"]["median"]) < 4.0
    assert held["out_of_sample"]["rms"] < held["in_sample"]["rms"] + 3.0
