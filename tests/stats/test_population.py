"""Population fits (`mcbat fit --population`, mcbat.stats.population.fit): parameters recovered
from tables simulated at known values, the real Statcast rows shipped in data/, and every
bad input refused with one line (exit 2)."""

import json
import math

import numpy as np
import pytest

import mcbat
from mcbat.statcast import read, write
from mcbat.stats.population.fit import fit_population, population_table, simulate_table
from tests.stats.population_shared import REAL, STUDY, assert_one_line_exit_2

TRUTH = {"swing.bat_speed.mean": 69.0, "swing.attack_angle.mean": 12.0,
         "contact.undercut.std": 0.9}


@pytest.fixture
def run_mcbat(cli):
    """``mcbat ARGS`` in this process (tests/cli_runner.py): the exit code, output and files
    these tests check are the command's, which an interpreter of its own would not change."""
    return cli


@pytest.fixture(scope="module")
def study():
    return mcbat.load_study(STUDY)


@pytest.fixture(scope="module")
def pitches():
    table, _ = population_table(read(REAL))
    return table




def test_injected_parameters_are_recovered(study, pitches):
    # One 400-row table simulated at known values (the real pitches, resampled): each
    # fitted value within 3 of its MINOS errors of the truth, and a sane goodness of fit.
    table = simulate_table(study, pitches, 400, seed=5, values=TRUTH)
    result = fit_population(study, table, list(TRUTH), draws=40, seed=1)
    assert result.rows == len(table) >= 390
    for p in result.parameters:
        truth = TRUTH[p["name"]]
        sigma = p["upper_error"] if truth > p["value"] else p["lower_error"]
        assert sigma is not None and sigma > 0, p
        assert abs(p["value"] - truth) < 3 * sigma, p
    cells = np.prod([len(e) + 1 for e in result.bins.values()])
    assert result.dof == cells - 1 - len(TRUTH)
    assert 0.001 < result.p_value <= 1.0
    assert result.effective_draws > 5 * result.rows


def test_physics_constant_by_grid(study, pitches):
    # e* is fitted through the grid of simulations, not by weights: recovered within 3 sigma
    # (with a parameter launch speed and angle tell apart from it: e* and the bat speed's
    # mean both set the launch speeds' level)
    values = {"e": 0.50, "swing.attack_angle.mean": 12.0}
    table = simulate_table(study, pitches, 300, seed=8, values=values)
    result = fit_population(study, table, list(values), draws=30, seed=2)
    for p in result.parameters:
        truth = values[p["name"]]
        sigma = p["upper_error"] if truth > p["value"] else p["lower_error"]
        assert abs(p["value"] - truth) < 3 * sigma, p


def test_real_statcast_fit_cli(tmp_path, run_mcbat):
    # the shipped day of 2020 games: the fit runs, with strict JSON, finite intervals and
    # a figure; the bat speed it gives is a bat speed (40-90 mph)
    figure = tmp_path / "population.png"
    # (the fit of docs/population.md, with fewer draws)
    proc = run_mcbat("fit", "--population", "--study", str(STUDY), "--data", str(REAL),
                  "--free", "swing.bat_speed.mean,swing.bat_speed.std,swing.attack_angle.mean,"
                  "swing.attack_angle.std,contact.undercut.std", "--draws", "40",
                  "--json", "--figure", str(figure))
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["rows"] > 300 and out["dof"] > 0 and math.isfinite(out["chi2"])
    values = {p["name"]: p for p in out["parameters"]}
    assert 40 < values["swing.bat_speed.mean"]["value"] < 90
    for p in out["parameters"]:
        assert p["lower_error"] is None or p["lower_error"] > 0
    assert figure.stat().st_size > 10_000


def test_template_that_cannot_cover_the_data(tmp_path, pitches, run_mcbat):
    # launch speeds in km/h: the fastest third lies beyond every draw of the study (the
    # table written as mcbat's tidy Parquet table, as `mcbat statcast --out` writes it)
    path = tmp_path / "kmh.parquet"
    table = pitches.copy()
    table["launch_speed"] *= 1.609344 * 1.5
    write(table, path)
    proc = run_mcbat("fit", "--population", "--study", str(STUDY), "--data", str(path),
                  "--free", "swing.bat_speed.mean", "--draws", "5")
    assert_one_line_exit_2(proc, "cannot cover the data")


def test_bad_options(run_mcbat):
    base = ("fit", "--population", "--study", str(STUDY), "--data", str(REAL))
    assert_one_line_exit_2(run_mcbat(*base), "--free")
    assert_one_line_exit_2(run_mcbat(*base, "--free", "swing.bat_speed.mean", "--observables",
                            "launch_speed,hang_time"), "--observables", "hang_time")
    assert_one_line_exit_2(run_mcbat(*base, "--free", "swing.bat_speed.mean", "--bins", "1"),
                     "--bins")
