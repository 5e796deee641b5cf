"""Fits of a game study to a Statcast-like table, and the draws' moments."""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.stats.fit.estimate import fit
from mcbat.stats.fit.likelihood import draw_moments
from mcbat.stats.measurements import synthesize
from mcbat.study import load_study
from tests.cli_runner import mcbat_main

ROOT = Path(__file__).resolve().parents[2]
GAME = load_study(Path(__file__).parent / "data" / "game_fit_fastball.toml")
TRUTH = {"e": 0.5, "e_x": 0.3}


# Both seeds check the same property on independent tables: the default run fits seed 6
# (test_game_fit_recovers_e_and_e_x[6], the faster), `pytest -m slow` seed 5 as well.
@pytest.mark.parametrize("seed", [pytest.param(5, marks=pytest.mark.slow), 6])
def test_game_fit_recovers_e_and_e_x(seed):
    """Launch speed, launch and spray angle and spin rate (Statcast's units), each row with
    its measured pitch speed, bat speed, attack angle and an undercut known to 2 mm: e* and
    e_x come back within their stated errors (two of them: a 1-sigma interval misses a
    third of the time; validation/interval_coverage.py setting g measures the coverage)."""
    table = synthesize(GAME, 100, seed=seed, **TRUTH, input_noise={"undercut": 0.002})
    assert {"launch_speed", "launch_angle", "spin_rate", "undercut_err"} <= set(table)
    assert 80 < table["launch_speed"].median() < 120  # mph
    result = fit(GAME, table, tuple(TRUTH), seed=seed)
    for name, value in TRUTH.items():
        iv = result.intervals[name]
        assert iv["status"] == "measured"
        err = iv["upper_error"] if value > result.params[name] else iv["lower_error"]
        assert 0 < err < 0.05
        assert abs(result.params[name] - value) < 2 * err
    assert result.dof == 4 * len(table) - 2
    assert 0.001 < result.p_value


@pytest.mark.parametrize("factor", [0.44704, 1.609344])  # m/s, km/h
def test_game_table_in_the_wrong_unit_is_refused(factor):
    table = synthesize(GAME, 40, seed=2, **TRUTH)
    table["launch_speed"] *= factor
    table["launch_speed_err"] *= factor
    with pytest.raises(InputError) as err:
        fit(GAME, table, ("e",), seed=2, intervals="curvature")
    assert err.value.field == "launch_speed" and "wrong unit" in str(err.value)


def test_game_fit_refuses_what_its_model_cannot_use():
    table = synthesize(GAME, 20, seed=3, **TRUTH)
    with pytest.raises(InputError) as err:
        fit(GAME, table, ("e", "axial"))
    assert err.value.field == "free" and "'axial' is not a parameter of a game" in str(err.value)
    drop = table.assign(exit_speed=30.0)
    with pytest.raises(InputError) as err:
        fit(GAME, drop, ("e",))
    assert err.value.field == "exit_speed" and "game study" in str(err.value)


def test_game_synth_and_fit_from_the_command_line(tmp_path, capsys):
    study = str(Path(__file__).parent / "data" / "game_fit_fastball.toml")
    data = tmp_path / "statcast_like.csv"
    code, _, stderr = mcbat_main(capsys, "synth", "--study", study, "--rows", "40", "--e",
                                 "0.5", "--e-x", "0.3", "--input-noise", "undercut=0.002",
                                 "--out", data)
    assert code == 0, stderr
    assert "undercut_err" in pd.read_csv(data).columns
    code, stdout, stderr = mcbat_main(capsys, "fit", "--study", study, "--data", data,
                                      "--free", "e,e_x", "--json", "--no-compare",
                                      "--intervals", "curvature")
    assert code == 0, stderr

    def strict(name):
        raise ValueError(name)

    result = json.loads(stdout, parse_constant=strict)
    assert abs(result["params"]["e"]["value"] - 0.5) < 5 * result["params"]["e"]["stderr"]
    code, _, stderr = mcbat_main(capsys, "synth", "--study", study, "--input-noise",
                                 "undercut")
    assert code == 2 and stderr.count("\n") == 1
    assert "--input-noise" in stderr and "Traceback" not in stderr


def test_draw_moments_independent_draws():
    """Independent draws: E[C + 2V] = Sigma (1 + 1/n), the variance of y - mean."""
    rng = np.random.default_rng(1)
    rows, n = 4000, 16
    cov = np.array([[4.0, 1.2], [1.2, 1.0]])
    sims = rng.multivariate_normal([1.0, -2.0], cov, size=(rows, n))
    ok = np.ones((rows, n), bool)
    mean, total = draw_moments(sims, ok)
    assert np.allclose(mean.mean(axis=0), [1.0, -2.0], atol=0.02)
    assert np.allclose(total.mean(axis=0), cov * (1 + 1 / n), rtol=0.03)
    ok[:, 3] = False  # a failed draw is left out of both terms
    sims[:, 3] = np.nan
    mean, total = draw_moments(sims, ok)
    assert np.isfinite(total).all()
    assert np.allclose(total.mean(axis=0), cov * (1 + 1 / (n - 1)), rtol=0.03)


def test_draw_moments_stratified_draws():
    """Draws in order of their slices (as a smeared measured input gives them): the error
    of the mean is nearly zero, so C + 2V is the spread, not the spread times (1 + 1/n)."""
    from scipy import stats

    rng = np.random.default_rng(2)
    rows, n = 2000, 48
    u = (np.arange(n) + rng.uniform(size=(rows, n))) / n
    sims = stats.norm.ppf(u)[:, :, None] * 2.0
    mean, total = draw_moments(sims, np.ones((rows, n), bool))
    assert np.std(mean) < 0.1 * 2.0 / np.sqrt(n)  # the mean is ten times better than iid ...
    assert abs(total.mean() / 4.0 - 1.0) < 0.01  # ... and the spread is not inflated


def test_bootstrap_gives_an_error_close_to_the_fit_error():
    study = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
    table = synthesize(study, 40, seed=9, e=0.6, mu=0.15)
    result = fit(study, table, ("e",), seed=9, bootstrap=8, intervals="curvature")
    boot, err = result.bootstrap_stderr["e"], result.stderr["e"]
    assert 0.3 * err < boot < 3 * err
    assert "bootstrap_stderr" in result.to_dict()["params"]["e"]
