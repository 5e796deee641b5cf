"""The fit on tables it did not simulate: a narrow likelihood valley in mu, measured inputs
beyond the study's range, intervals that cannot be computed, tables in the wrong unit."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from harness.drop_tables import drop_table, kernel_solver, reference_solver
from mcbat.errors import InputError
from mcbat.stats.fit import intervals as fitting
from mcbat.stats.fit.estimate import FitResult, Likelihood, fit
from mcbat.stats.measurements import read_measurements, synthesize
from mcbat.stats.models.input_priors import (
    PRIOR_DEGREE,
    WIDEN_P_VALUE,
    PriorFamily,
    beyond_range_test,
    prior_range,
)
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
DROP = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
GAME = load_study(ROOT / "studies" / "game_fastball.toml")
CASE = Path(__file__).parent / "data" / "fit_mu_limit_case.csv"


@pytest.fixture(scope="module")
def case_fit():
    return fit(DROP, read_measurements(CASE), ("e", "mu"), seed=0)


def test_a_valley_narrower_than_the_grid_is_found_and_holds_the_truth(case_fit):
    r = case_fit
    for name, truth in (("e", 0.6), ("mu", 0.18)):
        iv = r.intervals[name]
        assert iv["status"] == "measured", (name, iv)
        lo, hi = r.params[name] - iv["lower_error"], r.params[name] + iv["upper_error"]
        assert iv["lower_error"] > 0 and iv["upper_error"] > 0
        # 3 sigma: a measurement, not a 95 % limit at 0.218 that excludes the truth
        assert lo - 2 * iv["lower_error"] <= truth <= hi + 2 * iv["upper_error"], (name, lo, hi)
    assert 0.01 < r.p_value < 0.99


def test_the_best_fit_is_below_the_plateau_where_every_drop_sticks(case_fit):
    like = Likelihood(DROP, read_measurements(CASE), ("e", "mu"), seed=0)
    best = np.array([case_fit.params["e"], case_fit.params["mu"]])
    plateau = like(np.array([case_fit.params["e"], 2.0]))
    assert like(best) < plateau - 10  # the old answer, mu = 2, is 29 units of -ln L worse


def test_a_jumping_profile_is_reported_as_failed_not_as_a_zero_width_interval():
    def jump(t):  # the rise of -ln L jumps from 0 to 5 as soon as t leaves the best fit
        return 0.0 if t == 0.6 else 5.0
    side = fitting._side(jump, 0.6, 1, 1.0, 0.002, False)
    assert side.get("failed") and side["error"] is None
    other = fitting._side(lambda t: 0.5 * ((t - 0.6) / 0.002) ** 2, 0.6, -1, 1e-3, 0.002,
                          False)
    assert other["error"] == pytest.approx(0.002, rel=1e-2)
    entry = fitting._entry(other, side, lambda *a: None)
    assert entry["status"] == "profile_failed" and entry["lower_error"] is None
    r = FitResult(params={"e": 0.6}, stderr={"e": 0.002}, chi2=1.0, dof=1, p_value=0.3,
                  neg_log_likelihood=0.0, intervals={"e": entry})
    assert "could not be computed" in r.lines()[0]
    assert json.loads(json.dumps(r.to_dict()))["params"]["e"]["status"] == "profile_failed"


def test_the_prior_range_stays_the_studys_when_the_data_fit_it():
    rng = np.random.default_rng(5)
    sigma = np.full(3000, 0.005)
    inside = rng.uniform(-0.0254, 0.0254, 3000) + sigma * rng.standard_normal(3000)
    (lo, hi), p = prior_range(inside, sigma, (-0.0254, 0.0254), (-0.069, 0.069))
    assert p > WIDEN_P_VALUE and (lo, hi) == (-0.0254, 0.0254)
    wide = rng.uniform(-0.04, 0.04, 60) + sigma[:60] * rng.standard_normal(60)
    (lo, hi), p = prior_range(wide, sigma[:60], (-0.0254, 0.0254), (-0.069, 0.069))
    assert p < WIDEN_P_VALUE
    assert -0.05 < lo < -0.033 and 0.033 < hi < 0.05  # around the true +-4 cm


@pytest.mark.parametrize("rows", [20, 60, 3000])
def test_true_values_piled_at_the_ends_do_not_reject_the_range(rows):
    # The least favourable truth: every true value at an end of the range. The test's
    # p-values must then be no smaller than uniform: at most alpha of the tables rejected.
    rng = np.random.default_rng(rows)
    sigma = np.full(rows, 0.005)
    ends = np.where(np.arange(rows) % 2 == 0, -0.0254, 0.0254)
    p = np.array([beyond_range_test(ends + sigma * rng.standard_normal(rows), sigma,
                                    (-0.0254, 0.0254))[1] for _ in range(2000)])
    for alpha in (0.01, 0.05, 0.2):
        # binomial 4-sigma allowance above alpha
        assert (p < alpha).mean() < alpha + 4 * np.sqrt(alpha * (1 - alpha) / 2000)


def test_true_values_spread_beyond_the_range_reject_it():
    # 60 rows uniform in +-4 cm against a range of +-1 in. The test is built for a truth at
    # the range's ends, so it cannot catch every table: those it misses have few rows far
    # beyond. Most tables are rejected, and every one with eight rows 2 errors beyond
    # (the count alone then gives p = 3 P(K >= 8) < 0.001, K ~ Binomial(60, 0.023)).
    rng = np.random.default_rng(8)
    sigma = np.full(60, 0.005)
    rejected, clear = [], []
    for _ in range(200):
        measured = rng.uniform(-0.04, 0.04, 60) + sigma * rng.standard_normal(60)
        p = beyond_range_test(measured, sigma, (-0.0254, 0.0254))[1]
        rejected.append(p < WIDEN_P_VALUE)
        if (np.abs(measured) > 0.0254 + 2 * 0.005).sum() >= 8:
            clear.append(p < WIDEN_P_VALUE)
    assert np.mean(rejected) > 0.8 and all(clear) and len(clear) > 50


def test_the_range_test_agrees_with_its_statistics_by_hand():
    from scipy import stats

    # Two rows, one and three errors beyond each end of a range two errors wide.
    stat, p = beyond_range_test(np.array([-2.0, 4.0]), np.array([1.0, 1.0]), (-1.0, 1.0))
    assert stat == pytest.approx(10.0)

    def beyond(c):  # a row at an end lies c errors beyond: either side of a 2-error range
        return stats.norm.sf(c) + stats.norm.sf(c + 2.0)
    q = beyond(0.0)
    p_sum = 2 * q * (1 - q) * stats.chi2.sf(10.0, 1) + q * q * stats.chi2.sf(10.0, 2)
    c = beyond(2.0)
    p_count = 1 - (1 - c) ** 2  # one row of two more than 2 errors beyond
    p_max = 1 - (1 - beyond(3.0)) ** 2
    assert p == pytest.approx(3 * min(p_sum, p_count, p_max), rel=1e-9)
    assert beyond_range_test(np.array([0.0]), np.array([1.0]), (-1.0, 1.0)) == (0.0, 1.0)


@pytest.fixture(scope="module")
def wide_table():
    return drop_table(60, 1004, impact_parameter=(-0.04, 0.04), solver=kernel_solver)


def test_inputs_beyond_the_studys_range_widen_the_prior_and_say_so(wide_table, capsys):
    r = fit(DROP, wide_table, ("e", "mu"), seed=1, intervals="curvature")
    prior = r.priors["impact_parameter"]
    assert prior["widened"] and prior["range"][0] < -0.03 and prior["range"][1] > 0.03
    assert prior["study_range"] == pytest.approx([-0.0254, 0.0254])
    assert any("beyond the study's range" in w for w in r.warnings)
    # True values uniform in +-4 cm: 36.5 % of them beyond +-2.54 cm.
    assert 0.2 < prior["share_beyond_study_range"] < 0.55
    assert abs(r.params["mu"] - 0.18) < 4 * r.stderr["mu"]


def test_tables_the_range_test_lets_through_are_not_truncated():
    # A +-4 cm table whose measured values do not reject the study's range (p = 0.035,
    # above 0.01): with the study's range as the prior, mu came out 13 errors low. The
    # covering range and the fitted step put a fair share beyond, and mu holds the truth.
    table = drop_table(60, 1036, impact_parameter=(-0.04, 0.04), solver=kernel_solver)
    assert beyond_range_test(table["impact_parameter"].to_numpy(),
                             table["impact_parameter_err"].to_numpy(),
                             (-0.0254, 0.0254))[1] > WIDEN_P_VALUE
    r = fit(DROP, table, ("e", "mu"), seed=36, intervals="curvature")
    prior = r.priors["impact_parameter"]
    assert not prior["rejects_study_range"] and prior["share_beyond_study_range"] > 0.1
    assert any("beyond the study's range" in w for w in r.warnings)
    assert abs(r.params["mu"] - 0.18) < 3 * r.stderr["mu"]


def test_inputs_beyond_the_studys_range_are_refused_when_asked(wide_table):
    with pytest.raises(InputError) as err:
        fit(DROP, wide_table, ("e", "mu"), seed=1, intervals="curvature",
            input_prior="study")
    text = str(err.value)
    assert err.value.field == "impact_parameter"
    assert "rows" in text and "-0.0254..0.0254" in text
    assert "contact.impact_parameter" in text and "--input-prior cover" in text


def test_the_cli_refuses_with_one_line_and_exit_2(tmp_path, wide_table, capsys):
    from mcbat.cli import main

    path = tmp_path / "wide.csv"
    wide_table.to_csv(path, index=False)
    capsys.readouterr()
    # In this process: the interpreter's start-up adds nothing to the exit code and line.
    code = main(["fit", "--study", str(ROOT / "studies" / "cross_nathan_2006.toml"),
                 "--data", str(path), "--input-prior", "study", "--no-compare"])
    stderr = capsys.readouterr().err
    assert code == 2, stderr
    assert len(stderr.strip().splitlines()) == 1 and "impact_parameter" in stderr


def test_reference_and_kernel_make_the_same_table():
    ref = drop_table(4, 7, solver=reference_solver)
    ker = drop_table(4, 7, solver=kernel_solver)
    for col in ("exit_speed", "scattering_angle", "spin_out"):
        assert np.max(np.abs(ref[col] - ker[col]) / ref[f"{col}_err"]) < 1e-5


def _game_table(rows, columns):
    table = synthesize(GAME, rows, seed=11, e=0.5, e_x=0.3)
    table = table[[c for c in table.columns if c.split("_err")[0] in columns]].copy()
    return table


@pytest.mark.parametrize("columns", [("launch_speed", "launch_angle"),
                                     ("launch_speed", "launch_angle", "pitch_speed",
                                      "bat_speed"),
                                     ("launch_speed", "launch_angle", "spray_angle",
                                      "spin_rate", "pitch_speed", "bat_speed",
                                      "attack_angle", "undercut")])
def test_launch_speeds_in_metres_per_second_are_refused_whatever_the_table_holds(columns):
    table = _game_table(60, columns)
    table["launch_speed"] *= 0.44704
    if "launch_speed_err" in table:
        table["launch_speed_err"] *= 0.44704
    with pytest.raises(InputError) as err:
        fit(GAME, table, ("e",), seed=2, intervals="curvature")
    assert err.value.field == "launch_speed" and "m/s" in str(err.value)


def test_an_implausibly_good_fit_says_so():
    table = drop_table(60, 21, impact_parameter_err=0.0, solver=kernel_solver)
    plain = fit(DROP, table, ("e", "mu"), seed=2, intervals="curvature")
    assert not any("implausibly good" in w for w in plain.warnings)
    for col in ("exit_speed", "scattering_angle", "spin_out"):
        table[f"{col}_err"] *= 3  # stated errors three times the real ones
    r = fit(DROP, table, ("e", "mu"), seed=2, intervals="curvature")
    assert r.p_value > 0.995
    assert any("implausibly good" in w for w in r.warnings)


def test_e_far_from_the_studys_value_is_reported():
    table = _game_table(40, ("launch_speed", "launch_angle"))
    table["launch_speed"] *= 0.75
    r = fit(GAME, table, ("e",), seed=2, intervals="curvature")
    assert r.params["e"] < 0.33
    assert any("far from the study's value" in w for w in r.warnings)
    assert math.isfinite(r.chi2)


COEFFICIENTS = np.array([0.3, 1.5, -0.4, 0.8, -0.6, 0.4, 0.2, -0.3, 0.1, -0.1])
"""Coefficients of the log-density's Legendre polynomials, as many as the degree needs."""


def test_the_prior_family_is_a_normalised_density_with_its_gradient():
    family = PriorFamily(-0.0254, 0.0254)
    n = family.size
    assert n == PRIOR_DEGREE
    alpha = COEFFICIENTS[:n]
    grid = np.linspace(-0.0254, 0.0254, 200_001)
    density = family.density(grid, alpha)
    assert np.trapezoid(density, grid) == pytest.approx(1.0, rel=1e-9)
    assert family.density(grid, np.zeros(n)) == pytest.approx(1 / 0.0508)
    _, grad = family.log_norm(alpha)
    for j in range(n):
        step = np.eye(n)[j] * 1e-6
        numeric = (family.log_norm(alpha + step)[0] - family.log_norm(alpha - step)[0]) / 2e-6
        assert grad[j] == pytest.approx(numeric, rel=1e-6, abs=1e-9)


def test_a_prior_with_a_step_at_the_studys_range_is_normalised_with_its_gradient():
    family = PriorFamily(-0.04, 0.035, inner=(-0.0254, 0.0254))
    n = family.size
    assert family.step and n == PRIOR_DEGREE + 1
    alpha = np.append(COEFFICIENTS[:n - 1], -1.2)  # the last: the step's
    grid = np.linspace(-0.04, 0.035, 1_500_001)
    density = family.density(grid, alpha)
    assert np.trapezoid(density, grid) == pytest.approx(1.0, rel=1e-5)
    outside = (grid < -0.0254) | (grid > 0.0254)
    assert family.share_outside(alpha) == pytest.approx(
        np.trapezoid(np.where(outside, density, 0.0), grid), rel=1e-4)
    # Jumps by exp(alpha_s) at each end of the study's range.
    inner, outer = family.density(np.array([0.0254, np.nextafter(0.0254, 1.0)]), alpha)
    assert outer / inner == pytest.approx(math.exp(-1.2), rel=1e-9)
    _, grad = family.log_norm(alpha)
    for j in range(n):
        step = np.eye(n)[j] * 1e-6
        numeric = (family.log_norm(alpha + step)[0] - family.log_norm(alpha - step)[0]) / 2e-6
        assert grad[j] == pytest.approx(numeric, rel=1e-6, abs=1e-9)
    assert not PriorFamily(-0.0254, 0.0254, inner=(-0.0254, 0.0254)).step


def _mass_near_the_ends(family, alpha, width=0.007):
    """The prior's mass within ``width`` inside each end of the study's range."""
    grid = np.linspace(family.lo, family.hi, 200_001)
    density = family.density(grid, alpha)
    lo, hi = family.inner
    near = ((grid >= lo) & (grid < lo + width)) | ((grid <= hi) & (grid > hi - width))
    return float(np.trapezoid(np.where(near, density, 0.0), grid))


@pytest.mark.parametrize("setting,low,high", [("inside", 0.17, 0.4), ("edges", 0.6, 1.0)])
def test_the_fitted_prior_follows_the_true_values(setting, low, high):
    # 200 drops; a uniform truth puts 28 % of the mass within 7 mm of the ends, the edge
    # tables all of it.
    table = drop_table(200, 1000, solver=kernel_solver,
                       **({"edges": 0.005} if setting == "edges" else {}))
    like = Likelihood(DROP, table, ("e", "mu"), seed=0)
    like(np.array([0.6, 0.18]))
    family = like.prior_families["impact_parameter"]
    assert low < _mass_near_the_ends(family, like.prior_coefficients) < high


def test_draws_near_each_rows_posterior_resolve_the_likelihood_with_few_draws():
    # Table 116 of the validation's inside setting: five rows measured 2.3-3 errors from
    # their true impact parameter, where the draws of the measurement's posterior are
    # sparse. Without refinement 48 draws put the best mu (at e* = 0.6) near 0.170, 384 near
    # 0.176; with half of them placed near each row's posterior, 48 draws agree with 384.
    from harness.fit_validation import make_table

    table = make_table("inside", 116)
    mus = np.linspace(0.166, 0.184, 7)

    def curve(draws, refine):
        like = Likelihood(DROP, table, ("e", "mu"), draws=draws, seed=116)
        if refine:
            like.refine(np.array([0.6, 0.18]))
        nll = np.array([like(np.array([0.6, m])) for m in mus])
        return nll - nll.min()

    few, many = curve(48, True), curve(384, True)
    near = np.abs(mus - mus[np.argmin(many)]) < 0.0035  # within 2 errors (0.0016) of the best
    assert np.max(np.abs(few - many)[near]) < 0.15
    assert mus[np.argmin(few)] == mus[np.argmin(many)]
    plain = curve(48, False)
    assert mus[np.argmin(plain)] < mus[np.argmin(many)]  # what the refinement fixes
