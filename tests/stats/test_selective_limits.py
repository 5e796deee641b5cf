"""One-sided limits conditional on a flat profile (mcbat.stats.fit.selective).

The model is a drop test's friction in miniature: row i observes
slope * min(mu - stick_i, 0) + noise, flat in mu above its stick threshold. With one
fixed set of thresholds (the table's design), few noise draws give a profile flat above;
among those tables the likelihood-ratio limit holds the true mu in about three quarters,
and the conditional limit must hold it in about 95 %.
"""

import numpy as np
import pytest

from mcbat.stats.fit import selective
from mcbat.stats.fit.intervals import LIMIT_95, ONE_SIGMA
from mcbat.stats.fit.selective import (
    Surrogate,
    conditional_p_value,
    flat_side_mask,
    selective_limit,
    surrogate_rises,
)

TRUE_MU = 0.18
GRID = np.linspace(0.05, 0.5, 91)


def _design(rows=40, stick=(0.12, 0.2), slope=80.0, seed=1):
    thresholds = np.random.default_rng(seed).uniform(*stick, rows)
    curves = slope * np.minimum(GRID[:, None] - thresholds[None, :], 0.0)
    truth = slope * np.minimum(TRUE_MU - thresholds, 0.0)
    return curves, np.ones(rows), truth


def _likelihood_ratio_limit(rises):
    best = int(rises.argmin())
    beyond = np.nonzero(rises[:best + 1] >= LIMIT_95)[0]
    return GRID[beyond.max()] if len(beyond) else GRID[0]


def test_surrogate_rises_are_half_the_chi2_above_its_minimum():
    curves, variance, truth = _design(rows=5)
    y = truth + np.random.default_rng(3).standard_normal(5)
    chi2 = (((y - curves) ** 2) / variance).sum(axis=1)
    np.testing.assert_allclose(surrogate_rises(curves, variance, y), 0.5 * (chi2 - chi2.min()),
                               atol=1e-9)


def _weighted(log_w, sims, usable):
    w = np.where(usable, np.exp(log_w), 0.0)
    w /= w.sum(axis=1, keepdims=True)
    mean = (w[:, :, None] * sims).sum(axis=1)
    return w, mean, (w[:, :, None] * (sims - mean[:, None, :]) ** 2).sum(axis=1)


def test_the_statistic_weighs_the_draws_at_the_best_fit_and_the_null_at_the_value_tested():
    rng = np.random.default_rng(5)
    grid, rows, draws, obs = np.array([0.1, 0.2, 0.3]), 4, 6, 2
    sims = rng.normal(size=(3, rows, draws, obs))
    log_w = rng.normal(size=(3, rows, draws))
    best_sims, best_log_w = rng.normal(size=(rows, draws, obs)), rng.normal(size=(rows, draws))
    usable = np.ones((rows, draws), bool)
    usable[0, 2] = False  # a draw that failed somewhere weighs nothing
    s2 = rng.uniform(0.5, 2.0, (rows, obs))
    sur = Surrogate(grid, sims, log_w, best_sims, best_log_w, usable, s2,
                    rng.normal(size=rows * obs))
    curves, variance = sur.statistic()
    w, _, spread = _weighted(best_log_w, best_sims, usable)
    for g in range(3):
        np.testing.assert_allclose(curves[g], (w[:, :, None] * sims[g]).sum(axis=1).ravel(),
                                   rtol=1e-12)
    np.testing.assert_allclose(variance, (s2 + spread).ravel(), rtol=1e-12)
    for j in range(3):
        centre, null_variance = sur.null(j)
        _, mean, spread = _weighted(log_w[j], sims[j], usable)
        np.testing.assert_allclose(centre, mean.ravel(), rtol=1e-12)
        np.testing.assert_allclose(null_variance, (s2 + spread).ravel(), rtol=1e-12)
    # The null differs from the statistic's prediction where the weights differ.
    assert not np.allclose(sur.null(1)[0], curves[1])


def test_tables_simulated_around_the_null_decide_the_p_value(monkeypatch):
    # The same draws around the statistic's own prediction give the same p-value as the
    # default; drawn around a prediction nearer the plateau (the flat side), more of them
    # are flat and fewer rise as far at the value tested.
    monkeypatch.setattr(selective, "TABLES", 4000)
    monkeypatch.setattr(selective, "MIN_SELECTED", 200)
    curves, variance, _ = _design(rows=20, stick=(0.16, 0.2), slope=60.0)
    j = int(np.argmin(np.abs(GRID - TRUE_MU)))
    rise = 1.5
    same = conditional_p_value(curves, variance, rise, j, -1, np.random.default_rng(2),
                               ONE_SIGMA, null=lambda i: (curves[i], variance))
    default = conditional_p_value(curves, variance, rise, j, -1, np.random.default_rng(2),
                                  ONE_SIGMA)
    assert same == default
    nearer = 0.7 * curves[j] + 0.3 * curves[-1]
    shifted = conditional_p_value(curves, variance, rise, j, -1, np.random.default_rng(2),
                                  ONE_SIGMA, null=lambda i: (nearer, variance))
    assert shifted > default + 0.05


def test_flat_side_is_read_from_the_minimum_towards_the_chosen_end():
    rises = np.array([[3.0, 1.0, 0.0, 0.2, 0.4],    # flat above, bounded below
                      [0.4, 0.0, 0.3, 2.0, 5.0],    # flat below, bounded above
                      [2.0, 0.0, 0.2, 0.9, 0.1]])   # rises above 1/2, then falls back
    assert flat_side_mask(rises, -1, ONE_SIGMA).tolist() == [True, False, False]
    assert flat_side_mask(rises, 1, ONE_SIGMA).tolist() == [False, True, False]


@pytest.mark.slow
def test_conditional_limits_hold_the_truth_where_likelihood_ratio_limits_do_not(monkeypatch):
    # Fewer simulated tables than a fit's: each p-value is then known to about 2 % near
    # 5 %, which spreads the limits but does not bias their coverage.
    monkeypatch.setattr(selective, "TABLES", 5000)
    monkeypatch.setattr(selective, "MIN_SELECTED", 100)
    monkeypatch.setattr(selective, "MAX_TABLES", 40_000)
    curves, variance, truth = _design()
    rng = np.random.default_rng(7)
    y = truth + rng.standard_normal((8000, len(truth)))
    rises = surrogate_rises(curves, variance, y)
    flat = np.nonzero(flat_side_mask(rises, -1, ONE_SIGMA))[0][:40]
    assert len(flat) == 40  # about 1.4 % of tables are flat above
    ratio = [_likelihood_ratio_limit(rises[k]) <= TRUE_MU for k in flat]
    conditional = []
    for k in flat:
        limit, p_values = selective_limit(GRID, curves, variance, y[k], -1, rng, ONE_SIGMA)
        assert limit is not None and limit <= _likelihood_ratio_limit(rises[k]) + 1e-12
        conditional.append(limit <= TRUE_MU)
    # Over all such tables the likelihood-ratio limits hold the truth in 75 %, the
    # conditional ones in 95 %: 38 of 40 expected, 34 is 3 standard deviations below.
    assert np.mean(ratio) < 0.85
    assert np.mean(conditional) >= 34 / 40


@pytest.mark.parametrize("sign", [-1, 1])
def test_a_profile_bounded_on_both_sides_gives_no_conditional_limit(sign):
    # Data made at mu = 0.12, below every stick threshold: the profile rises on both sides
    # (read from either end of the grid).
    curves, variance, _ = _design(rows=20)
    y = curves[np.argmin(np.abs(GRID - 0.12))]
    curves = curves if sign < 0 else curves[::-1]
    assert not flat_side_mask(surrogate_rises(curves, variance, y), sign, ONE_SIGMA)[0]
    limit, p_values = selective_limit(GRID, curves, variance, y, sign,
                                      np.random.default_rng(0), ONE_SIGMA)
    assert limit is None and p_values == {}


def test_the_conditional_p_value_of_the_truth_is_uniform_over_tables_flat_above(monkeypatch):
    # The test behind a conditional limit, applied to the true value of each table that
    # reports a limit, must reject it at its nominal rate at every level: its p-values are
    # uniform. Tables are drawn from the surrogate itself, so only the construction (the
    # selection, the statistic, the simulated tables) is under test.
    monkeypatch.setattr(selective, "TABLES", 4000)
    monkeypatch.setattr(selective, "MIN_SELECTED", 200)
    curves, variance, _ = _design(rows=20, stick=(0.16, 0.2), slope=60.0)
    j = int(np.argmin(np.abs(GRID - TRUE_MU)))
    rng = np.random.default_rng(11)
    y = curves[j] + rng.standard_normal((4000, len(variance)))
    rises = surrogate_rises(curves, variance, y)
    flat = np.nonzero(flat_side_mask(rises, -1, ONE_SIGMA))[0][:300]
    assert len(flat) == 300
    p = np.array([conditional_p_value(curves, variance, rises[k, j], j, -1, rng, ONE_SIGMA)
                  for k in flat])
    for level in (0.05, 0.2, 0.5):
        # Within 3.5 binomial errors of the level (the levels are not independent).
        error = np.sqrt(level * (1 - level) / len(p))
        assert abs((p <= level).mean() - level) < 3.5 * error, level
    # Without the condition the same statistic is not calibrated among these tables: the
    # data flat above rise far at the truth, and the unconditional p-value (the share of
    # all simulated tables rising as far) is too often small.
    z = rng.standard_normal((20000, len(variance)))
    all_rises = surrogate_rises(curves, variance, curves[j] + z)[:, j]
    unconditional = np.array([(all_rises >= rises[k, j]).mean() for k in flat])
    assert (unconditional <= 0.2).mean() > 0.2 + 3.5 * np.sqrt(0.16 / len(p))
