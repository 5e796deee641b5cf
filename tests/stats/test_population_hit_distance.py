"""The distance as an observable of population fits (``--observables ...,hit_distance``):
Statcast's ``hit_distance_sc`` read as ``hit_distance``, rows without one left out and
counted, the flight flown on every engine, the real balls in play fitted, an injected table
recovered with and without the distance, and every bad input refused with one line."""

import csv
import json
import math

import numpy as np
import pytest

import mcbat
from mcbat.errors import InputError
from mcbat.statcast import read
from mcbat.stats.population.fit import fit_population, population_table, simulate_table
from mcbat.stats.population.templates import TemplateSimulator
from tests.stats.population_shared import ROOT, STUDY, assert_one_line_exit_2, run_mcbat

FLIGHT_STUDY = ROOT / "studies" / "game_fastball.toml"  # a game with a [flight] section
IN_PLAY = ROOT / "data" / "statcast_2020-09-03_in_play.csv"  # 424 real balls in play
WITH_DISTANCE = ("launch_speed", "launch_angle", "hit_distance")


@pytest.fixture(scope="module")
def study():
    return mcbat.load_study(FLIGHT_STUDY)


@pytest.fixture(scope="module")
def in_play():
    return read(IN_PLAY)


def test_statcast_distance_is_the_observable(in_play):
    # the tidy table's hit_distance_sc, row for row; every ball in play of the day has one
    data, dropped = population_table(in_play, WITH_DISTANCE)
    assert len(data) == 424 and dropped["no_hit_distance"] == 0
    used = in_play[np.isfinite(in_play["launch_speed"])]
    np.testing.assert_array_equal(data["hit_distance"], used["hit_distance_sc"])
    assert data["hit_distance"].between(1, 460).all()  # ft: a few feet to home runs


def test_rows_without_a_distance_are_left_out_and_counted(in_play):
    table = in_play.copy()
    rows = np.flatnonzero(np.isfinite(table["launch_speed"]))[[0, 5, 9, 40, 41]]
    table.loc[rows, "hit_distance_sc"] = np.nan
    data, dropped = population_table(table, WITH_DISTANCE)
    assert len(data) == 419 and dropped["no_hit_distance"] == 5
    assert np.isfinite(data["hit_distance"]).all()
    # without the distance among the observables the same rows are all used
    data, dropped = population_table(table)
    assert len(data) == 424 and "no_hit_distance" not in dropped


def test_fit_says_it_left_rows_without_a_distance_out(study, in_play):
    table = in_play.copy()
    rows = np.flatnonzero(np.isfinite(table["launch_speed"]))[:7]
    table.loc[rows, "hit_distance_sc"] = np.nan
    result = fit_population(study, table, ["swing.bat_speed.mean", "contact.undercut.mean"],
                            draws=20, seed=3, bins=4, observables=WITH_DISTANCE, passes=1)
    assert result.rows == 417 and result.dropped["no_hit_distance"] == 7
    assert any(w.startswith("7 batted balls without a measured distance (hit_distance_sc)")
               for w in result.warnings), result.warnings
    assert result.to_dict()["dropped"]["no_hit_distance"] == 7


def test_table_without_the_distance_is_refused(in_play):
    with pytest.raises(InputError, match="hit_distance_sc") as err:
        population_table(in_play.drop(columns="hit_distance_sc"), WITH_DISTANCE)
    assert err.value.field == "hit_distance"
    empty = in_play.assign(hit_distance_sc=np.nan)
    with pytest.raises(InputError, match="no rows with") as err:
        population_table(empty, WITH_DISTANCE)
    assert err.value.field == "hit_distance_sc"


def test_simulated_table_holds_only_simulated_distances(study, in_play):
    # pitches taken from a table read with the distance: the simulated table's distance,
    # under either name, is the flown one, never the resampled pitch's own ball's
    pitches, _ = population_table(in_play, WITH_DISTANCE)
    table = simulate_table(study, pitches, 200, seed=4)
    np.testing.assert_array_equal(table["hit_distance"], table["hit_distance_sc"])
    data, _ = population_table(table, WITH_DISTANCE)
    sim = TemplateSimulator(study, pitches, 200, 4, "memory", None, flight=True)
    try:
        _, observed, ok = sim.run({}, {}, ["pitch_speed"], WITH_DISTANCE)
    finally:
        sim.close()
    np.testing.assert_array_equal(data["hit_distance"], observed["hit_distance"][ok])
    # a study without a flight writes no distance at all
    plain = simulate_table(mcbat.load_study(STUDY), pitches, 50, seed=4)
    assert plain["hit_distance_sc"].isna().all() and plain["hit_distance"].isna().all()


def test_engines_fly_the_same_balls(study, in_play, tmp_path):
    # the local engine (run_study of the study with its [flight], read back) and the
    # in-process solve give the same distances, to the last digit
    data, _ = population_table(in_play, WITH_DISTANCE)
    data = data.iloc[:40]
    out = {}
    for engine in ("memory", "local"):
        sim = TemplateSimulator(study, data, 400, 6, engine, tmp_path / engine, flight=True)
        try:
            out[engine] = sim.run({}, {}, ["pitch_speed"], WITH_DISTANCE)
        finally:
            sim.close()
    (_, m_obs, m_ok), (_, l_obs, l_ok) = out["memory"], out["local"]
    np.testing.assert_array_equal(m_ok, l_ok)
    assert m_ok.mean() > 0.95
    for name in WITH_DISTANCE:
        np.testing.assert_array_equal(m_obs[name][m_ok], l_obs[name][l_ok])
    # a distance is a distance: grounders a few feet, the longest flies 400+ ft
    d = m_obs["hit_distance"][m_ok]
    assert d.min() < 20 and 380 < d.max() < 520


REAL_FIT = ("fit", "--population", "--study", str(FLIGHT_STUDY), "--data", str(IN_PLAY),
            "--free", "swing.bat_speed.mean,contact.undercut.mean", "--observables",
            ",".join(WITH_DISTANCE), "--bins", "4")


def test_real_balls_in_play_fit_with_the_distance_json():
    # the 424 balls in play of 2020-09-03 in launch speed x angle x distance (4 bins an
    # axis): a fit and its goodness of fit. A launch speed and angle give one distance, so
    # many of the 64 cells hold no draw and no ball: they count no degree of freedom.
    proc = run_mcbat(*REAL_FIT, "--draws", "20", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["observables"] == list(WITH_DISTANCE)
    assert out["rows"] == 424 and out["dropped"]["no_hit_distance"] == 0
    assert len(out["bins"]["hit_distance"]) == 3  # interior edges, ft
    assert out["cells"]["total"] == 4**3 and 20 < out["cells"]["used"] < 4**3
    assert out["dof"] == out["cells"]["used"] - 1 - 2
    assert math.isfinite(out["chi2"]) and out["chi2"] > 0 and 0.0 <= out["p_value"] <= 1.0
    values = {p["name"]: p["value"] for p in out["parameters"]}
    assert 60 < values["swing.bat_speed.mean"] < 80


def test_real_balls_in_play_fit_with_the_distance_text():
    proc = run_mcbat(*REAL_FIT, "--draws", "10")
    assert proc.returncode == 0, proc.stderr
    assert "424 batted balls" in proc.stdout
    assert "in launch_speed x launch_angle x hit_distance" in proc.stdout
    assert "chi2 / dof = " in proc.stdout


def test_study_without_flight_is_refused():
    proc = run_mcbat("fit", "--population", "--study", str(STUDY), "--data", str(IN_PLAY),
                     "--free", "swing.bat_speed.mean", "--observables",
                     "launch_speed,hit_distance")
    assert_one_line_exit_2(proc, "--observables", "hit_distance", "[flight]")


def test_export_without_distances_is_refused(tmp_path):
    # a Savant export whose hit_distance_sc cells are all empty: one line naming the column
    path = tmp_path / "no_distances.csv"
    with open(IN_PLAY, newline="") as src, open(path, "w", newline="") as dst:
        reader = csv.DictReader(src)
        writer = csv.DictWriter(dst, reader.fieldnames)
        writer.writeheader()
        for row in reader:
            writer.writerow({**row, "hit_distance_sc": ""})
    proc = run_mcbat("fit", "--population", "--study", str(FLIGHT_STUDY), "--data",
                     str(path), "--free", "swing.bat_speed.mean", "--observables",
                     ",".join(WITH_DISTANCE))
    assert_one_line_exit_2(proc, "hit_distance_sc", "no rows with")


TRUTH = {"swing.bat_speed.mean": 68.0, "contact.undercut.mean": 0.4}


def _pulls(result):
    out = {}
    for p in result.parameters:
        truth = TRUTH[p["name"]]
        sigma = p["upper_error"] if truth > p["value"] else p["lower_error"]
        assert sigma is not None and sigma > 0, p
        out[p["name"]] = (p["value"] - truth) / sigma
    return out


def test_distance_does_not_bias_injected_values(study, in_play):
    # Three 400-row tables simulated at known values (the real pitches of the day,
    # resampled; each ball flown): fitted with and without the distance, every value lies
    # within 3 of its MINOS errors of the truth, and the mean pull over the tables with the
    # distance is within 3 of its standard error (1 / sqrt(3)) of zero.
    pitches, _ = population_table(in_play)
    with_distance = []
    for seed in (11, 12, 13):
        table = simulate_table(study, pitches, 400, seed=seed, values=TRUTH)
        assert np.isfinite(table["hit_distance_sc"]).all()
        kw = {"seed": seed + 100, "bins": 4}  # (the default 100 draws a row)
        result = fit_population(study, table, list(TRUTH), observables=WITH_DISTANCE, **kw)
        assert result.p_value > 0.001, (result.chi2, result.dof)
        pulls = _pulls(result)
        without = _pulls(fit_population(study, table, list(TRUTH), **kw))
        assert all(abs(v) < 3 for v in (*pulls.values(), *without.values())), (pulls, without)
        with_distance.append(list(pulls.values()))
    assert np.all(np.abs(np.mean(with_distance, axis=0)) < 3 / math.sqrt(3)), with_distance
