"""Two-sample statistics on plain arrays: are two samples of one quantity drawn from one
distribution? (``mcbat compare``, ``mcbat.stats.compare.comparison``, ``docs/compare.md``)

* ``ks_test``: the two-sample Kolmogorov-Smirnov distance ``D = max |F - G|`` of the
  two empirical distribution functions, with scipy's p-value (``scipy.stats.ks_2samp``,
  ``method="auto"``: the exact distribution for small samples, the asymptotic one
  otherwise). It assumes continuous data; rounded values (Statcast's launch angles are
  whole degrees) make it conservative.
* ``wasserstein``: the 1-D Wasserstein (earth mover's) distance ``∫ |F - G| dx``, in the
  column's unit: how far, on average, the measured distribution must be moved to become the
  simulated one.
* ``energy_test``: the energy distance ``sqrt(2 E|X-Y| - E|X-X'| - E|Y-Y'|)``
  (Székely and Rizzo; ``scipy.stats.energy_distance``'s definition, in the column's unit)
  with a permutation p-value.
* ``plane_energy_test``: the energy distance of two samples of points in the plane,
  on coordinates standardized by the pooled sample's standard deviations (so that mph and
  degrees weigh alike, and the scaling is the same under every permutation), with a
  permutation p-value.

Permutation p-values are ``(1 + k) / (1 + P)``, ``k`` the number of the ``P`` random
relabellings of the pooled sample whose statistic reaches the observed one: valid at any
sample size, never 0, with a resolution of ``1 / (1 + P)``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from mcbat.errors import InputError

__all__ = ["PERMUTATIONS", "energy_test", "format_p", "ks_test", "plane_energy_test",
           "wasserstein"]

PERMUTATIONS = 1000
"""Default number of random relabellings of a permutation test (p-value resolution 1/1001)."""


def ks_test(x, y):
    """Two-sample Kolmogorov-Smirnov distance and p-value (``scipy.stats.ks_2samp``).

    Returns
    -------
    dict
        ``statistic`` (``max |F - G|``), ``p_value``, ``method`` (``"exact"`` or
        ``"asymptotic"``: scipy's choice for these sizes).
    """
    from scipy import stats

    x, y = _finite(x, "x"), _finite(y, "y")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = stats.ks_2samp(x, y, method="auto")
    # scipy's "auto" uses the exact distribution up to 10,000 rows on the larger side, and
    # falls back to the asymptotic one (with a warning) where the exact sum fails
    method = "exact" if max(len(x), len(y)) <= 10_000 else "asymptotic"
    if any("asymp" in str(w.message) for w in caught):
        method = "asymptotic"
    return {"statistic": float(result.statistic), "p_value": float(result.pvalue),
            "method": method}


def wasserstein(x, y):
    """The 1-D Wasserstein distance ``∫ |F - G| dx`` (in the values' unit)."""
    from scipy import stats

    return float(stats.wasserstein_distance(_finite(x, "x"), _finite(y, "y")))


def energy_test(x, y, permutations=PERMUTATIONS, seed=0):
    """Energy distance of two 1-D samples and its permutation p-value.

    The distance is ``sqrt(2 E|X-Y| - E|X-X'| - E|Y-Y'|) = sqrt(2 ∫ (F - G)^2 dx)`` over the
    empirical distributions (``scipy.stats.energy_distance``'s definition), in the values'
    unit. Each relabelling of the pooled sample is evaluated on the sorted pooled values
    (cumulative counts of each label): ``O(n + m)`` per permutation.

    Parameters
    ----------
    x, y : array_like
        Finite values (at least one each).
    permutations : int
        Random relabellings (0: no p-value).
    seed : int or sequence of int
        Seed of ``numpy.random.default_rng``: the same seed gives the same p-value.

    Returns
    -------
    dict
        ``distance``, ``p_value`` (None without permutations), ``permutations``.
    """
    x, y = _finite(x, "x"), _finite(y, "y")
    pooled = np.concatenate([x, y])
    order = np.argsort(pooled, kind="stable")
    dz = np.diff(pooled[order])
    labels = np.zeros(pooled.size, dtype=bool)
    labels[:x.size] = True
    labels = labels[order]
    observed = _energy_sq_sorted(dz, labels[None, :], x.size, y.size)[0]
    p_value = _permutation_p(observed, labels, permutations, seed,
                             lambda batch: _energy_sq_sorted(dz, batch, x.size, y.size))
    return {"distance": math.sqrt(max(observed, 0.0)), "p_value": p_value,
            "permutations": int(permutations)}


def _energy_sq_sorted(dz, labels, n_x, n_y):
    """``2 ∫ (F - G)^2`` for each row of ``labels`` (bool, the pooled values' sorted
    order; True for ``x``), ``dz`` the gaps between the sorted pooled values."""
    below_x = np.cumsum(labels[:, :-1], axis=1, dtype=np.int64)
    below = np.arange(1, labels.shape[1], dtype=np.int64)
    gap = below_x / n_x - (below - below_x) / n_y
    return 2.0 * (gap * gap) @ dz


def plane_energy_test(x, y, permutations=PERMUTATIONS, seed=0):
    """Energy distance of two samples of points in the plane (or any dimension), on
    coordinates standardized by the pooled sample, and its permutation p-value.

    Each coordinate is divided by its standard deviation over the pooled sample, which is
    the same under every relabelling; the distance is then
    ``sqrt(2 E|X-Y| - E|X-X'| - E|Y-Y'|)`` with Euclidean ``|.|`` (dimensionless). The
    pooled sample's distance matrix is computed once, and each relabelling's within- and
    between-sample sums come from one matrix product with the label vectors, so the
    memory is ``8 (n + m)^2`` bytes: subsample large samples first (``PLANE_ROWS``).

    Parameters
    ----------
    x, y : array_like, shape (n, d) and (m, d)
        Finite points.
    permutations, seed
        As ``energy_test``.

    Returns
    -------
    dict
        ``distance``, ``p_value`` (None without permutations), ``permutations``, ``scale``
        (the pooled standard deviation of each coordinate).
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.ndim != 2 or y.ndim != 2 or x.shape[1] != y.shape[1]:
        raise InputError("x", "expected two arrays of points of one dimension, shapes "
                         f"(n, d) and (m, d); got {x.shape} and {y.shape}")
    if len(x) == 0 or len(y) == 0 or not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise InputError("x", "expected finite points, at least one on each side")
    pooled = np.concatenate([x, y])
    scale = pooled.std(axis=0)
    scale[scale == 0] = 1.0
    z = pooled / scale
    n_x, n_y = len(x), len(y)
    distances = np.empty((len(z), len(z)))
    for start in range(0, len(z), 512):  # in blocks: no (N, N, d) temporary
        block = z[start:start + 512]
        distances[start:start + 512] = np.sqrt(
            ((block[:, None, :] - z[None, :, :]) ** 2).sum(axis=2))
    row_sums = distances.sum(axis=1)
    total = row_sums.sum()

    def statistic(labels):  # labels: (B, N) bool, True for x
        weights = labels.astype(float)
        within_x = np.einsum("bi,bi->b", weights @ distances, weights)
        between = weights @ row_sums - within_x
        within_y = total - 2.0 * between - within_x
        return 2.0 * between / (n_x * n_y) - within_x / n_x**2 - within_y / n_y**2

    labels = np.zeros(len(z), dtype=bool)
    labels[:n_x] = True
    observed = statistic(labels[None, :])[0]
    p_value = _permutation_p(observed, labels, permutations, seed, statistic, batch=64)
    return {"distance": math.sqrt(max(observed, 0.0)), "p_value": p_value,
            "permutations": int(permutations), "scale": [float(s) for s in scale]}


def _permutation_p(observed, labels, permutations, seed, statistic, batch=256):
    """``(1 + k) / (1 + P)``: ``k`` of ``P`` random relabellings reach ``observed``."""
    if permutations < 0:
        raise InputError("permutations", f"must be an integer >= 0, got {permutations}")
    if permutations == 0:
        return None
    rng = np.random.default_rng(seed)
    # a relabelling that reproduces the observed one must count: allow for the rounding of
    # sums taken in another order
    threshold = observed - 1e-12 * abs(observed)
    reached = 0
    for start in range(0, permutations, batch):
        count = min(batch, permutations - start)
        shuffled = rng.permuted(np.broadcast_to(labels, (count, labels.size)), axis=1)
        reached += int((statistic(shuffled) >= threshold).sum())
    return (1.0 + reached) / (1.0 + permutations)


def _finite(values, name):
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0 or not np.isfinite(values).all():
        raise InputError(name, "expected finite values, at least one")
    return values


def format_p(p, resolution):
    """A p-value as printed: ``"-"`` for none, ``"<=0.001"`` at a permutation test's
    resolution (the smallest p-value it can give), else three significant digits."""
    if p is None:
        return "-"
    if resolution is not None and p <= resolution * (1 + 1e-9):
        return f"<={p:.2g}"
    return f"{p:.3g}" if p >= 1e-3 else f"{p:.1e}"
