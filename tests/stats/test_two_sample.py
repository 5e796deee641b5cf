"""Two-sample statistics of mcbat.stats.compare.two_sample, against direct formulas and on samples
whose answer is known (the same distribution, shifted ones)."""

import itertools
import math

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from mcbat.stats.compare.two_sample import energy_test, ks_test, plane_energy_test, wasserstein


def _ecdf(sample, at):
    return np.searchsorted(np.sort(sample), at, side="right") / len(sample)


def _direct_energy(x, y):
    x, y = np.atleast_2d(np.asarray(x, float).T).T, np.atleast_2d(np.asarray(y, float).T).T
    value = 2 * cdist(x, y).mean() - cdist(x, x).mean() - cdist(y, y).mean()
    return math.sqrt(value)


SMALL = [
    (np.array([0.3, 1.2, -0.7, 2.5, 0.0]), np.array([1.1, 3.0, 2.2, 0.4])),
    (np.array([1.0, 1.0, 2.0, 3.0, 3.0, 3.0]), np.array([2.0, 2.0, 3.0, 4.0])),  # ties
    (np.array([5.0]), np.array([-1.0, 0.0, 7.5])),
]


@pytest.mark.parametrize("x, y", SMALL)
def test_ks_wasserstein_and_energy_equal_their_direct_formulas(x, y):
    grid = np.union1d(x, y)
    gap = np.abs(_ecdf(x, grid) - _ecdf(y, grid))
    assert ks_test(x, y)["statistic"] == pytest.approx(gap.max(), abs=1e-15)
    # W1 = integral of |F - G| between consecutive pooled values
    assert wasserstein(x, y) == pytest.approx((gap[:-1] * np.diff(grid)).sum(), rel=1e-12)
    assert energy_test(x, y, permutations=0)["distance"] == pytest.approx(
        _direct_energy(x, y), rel=1e-12)


def test_plane_energy_equals_the_direct_formula_on_standardized_points():
    rng = np.random.default_rng(3)
    x = rng.normal([90, 12], [10, 20], size=(40, 2))
    y = rng.normal([95, 15], [12, 25], size=(25, 2))
    scale = np.concatenate([x, y]).std(axis=0)
    result = plane_energy_test(x, y, permutations=0)
    assert result["distance"] == pytest.approx(_direct_energy(x / scale, y / scale), rel=1e-12)
    assert result["scale"] == pytest.approx(list(scale), rel=1e-14)
    assert result["p_value"] is None


def _exact_permutation_p(x, y, statistic):
    """The p-value over every split of the pooled sample (the exact permutation test)."""
    pooled = np.concatenate([x, y])
    observed = statistic(x, y)
    splits = list(itertools.combinations(range(len(pooled)), len(x)))
    reached = 0
    for chosen in splits:
        mask = np.zeros(len(pooled), bool)
        mask[list(chosen)] = True
        reached += statistic(pooled[mask], pooled[~mask]) >= observed - 1e-12
    return reached / len(splits)


def test_permutation_p_values_approach_the_exact_test():
    x = np.array([0.1, 0.9, 1.7, 2.2, 3.1])
    y = np.array([1.5, 2.8, 3.3, 4.0, 4.4, 5.2])
    exact = _exact_permutation_p(x, y, _direct_energy)  # 462 splits
    got = energy_test(x, y, permutations=20000, seed=1)["p_value"]
    assert got == pytest.approx(exact, abs=4 * math.sqrt(exact * (1 - exact) / 20000))
    xy, yy = np.column_stack([x, x**2]), np.column_stack([y, 0.5 * y])

    def plane(a, b):
        scale = np.concatenate([xy, yy]).std(axis=0)  # pooled: the same for every split
        return _direct_energy(a / scale, b / scale)
    exact = _exact_permutation_p(xy, yy, plane)
    got = plane_energy_test(xy, yy, permutations=20000, seed=1)["p_value"]
    assert got == pytest.approx(exact, abs=4 * math.sqrt(exact * (1 - exact) / 20000))


def test_samples_of_one_distribution_are_not_rejected():
    """Over 20 seeds the p-values spread over (0, 1): rejections at 5 % stay rare."""
    ks_p, energy_p, plane_p = [], [], []
    for seed in range(20):
        rng = np.random.default_rng(seed)
        x, y = rng.normal(size=(2000, 2)), rng.normal(size=(150, 2))
        ks_p.append(ks_test(x[:, 0], y[:, 0])["p_value"])
        energy_p.append(energy_test(x[:, 0], y[:, 0], permutations=200, seed=seed)["p_value"])
        plane_p.append(plane_energy_test(x[:400], y, permutations=200, seed=seed)["p_value"])
    for p in (ks_p, energy_p, plane_p):
        # Binomial(20, 0.05): 5 or more rejections has probability 0.003
        assert sum(v < 0.05 for v in p) <= 4, p
        assert 0.3 < np.mean(p) < 0.7, p


def test_shifted_samples_are_rejected_and_the_statistics_grow_with_the_shift():
    rng = np.random.default_rng(7)
    x, y = rng.normal(size=3000), rng.normal(size=300)
    ks_d, w, energy, plane = [], [], [], []
    for shift in (0.0, 0.3, 0.6, 1.2):
        ks = ks_test(x, y + shift)
        e = energy_test(x, y + shift, permutations=300, seed=0)
        pl = plane_energy_test(np.column_stack([x[:600], x[600:1200]]),
                               np.column_stack([y + shift, y[::-1]]), permutations=300)
        ks_d.append(ks["statistic"])
        w.append(wasserstein(x, y + shift))
        energy.append(e["distance"])
        plane.append(pl["distance"])
        if shift >= 0.3:
            assert ks["p_value"] < 1e-3
            assert e["p_value"] == pytest.approx(1 / 301)  # none of 300 relabellings reach it
            assert pl["p_value"] == pytest.approx(1 / 301)
    for values in (ks_d, w, energy, plane):
        assert np.all(np.diff(values) > 0), values
    # W1 lies between the difference of the means and the shift plus W1 unshifted
    assert abs(np.mean(y) + 1.2 - np.mean(x)) <= w[-1] <= 1.2 + w[0] + 1e-12


def test_permutation_p_value_is_reproducible_and_seeded():
    rng = np.random.default_rng(0)
    x, y = rng.normal(size=500), rng.normal(0.1, 1, size=80)
    a = energy_test(x, y, permutations=300, seed=5)
    assert energy_test(x, y, permutations=300, seed=5) == a
    assert 1 / 301 <= a["p_value"] <= 1
