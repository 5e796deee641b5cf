"""The true values of a measured input: the range a fit marginalises them over, and the
estimated prior over it.

The range a measured input's true values are marginalised over depends on
``input_prior``:

* ``"cover"`` (what the mixture likelihood uses by default): the study's range widened to
  cover every measured value and ``COVER_SIGMA`` of its errors (never beyond the
  input's physical range). The estimated prior has a step at each end of the study's
  range (``PriorFamily``), fitted with the rest: a table whose true values stay
  within the study's range fits the step far down (the study's range, in effect), one
  whose true values reach beyond fits it up, and nothing is truncated.
* ``"widen"`` (the normal likelihood's default): the study's range, unless the measured
  values reject it (``beyond_range_test``, ``prior_range``): then the range that
  best explains them (the study's range widened, never narrowed, never beyond the
  physical range).
* ``"study"``: the study's range, and a table whose measured values reject it is refused.

Truncating each row's true value to a range the data reach beyond would bias the fit
without a word (rows measured 2-3 errors beyond the edge forced onto it). Every fit
reports the range it used (``mcbat.stats.models.draws._DrawModel.priors``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize, stats

__all__ = ["COVER_SIGMA", "INPUT_PRIORS", "PRIOR_DEGREE", "PRIOR_RIDGE", "PriorFamily",
           "WIDEN_P_VALUE", "beyond_range_test", "covering_range", "prior_range"]

INPUT_PRIORS = ("cover", "widen", "study")
"""The ranges a measured input's true values are marginalised over (module docstring)."""
COVER_SIGMA = 5.0
"""With ``input_prior = "cover"`` the range reaches this many errors beyond every measured
value (the posterior of a row's true value beyond it is below 3e-7 of the whole)."""
WIDEN_P_VALUE = 0.01
"""The measured values of an input reject the study's range when ``beyond_range_test``
gives a p-value below this: when every true value does lie within the study's range, that
happens in fewer than 1 % of tables, whatever their size and wherever in the range the
true values lie (the test is computed at the least favourable place, the range's ends; for
true values spread over the range, far more rarely). A rejection that is wrong costs
little (the fit marginalises over a wider range, with the prior's shape estimated), one
that is missed truncates the true values and biases the fit."""


def _range_log_likelihood(value, sigma, lo, hi):
    """``sum_i ln p(x_i)`` of measured values ``x_i +- sigma_i`` whose true values are
    uniform over ``[lo, hi]``: ``p(x) = (Phi((hi - x)/s) - Phi((lo - x)/s)) / (hi - lo)``."""
    mass = stats.norm.cdf((hi - value) / sigma) - stats.norm.cdf((lo - value) / sigma)
    return float(np.sum(np.log(np.maximum(mass, 1e-300))) - len(value) * math.log(hi - lo))


BEYOND_COUNT_SIGMA = 2.0
"""The count statistic of ``beyond_range_test`` counts rows more than this many of their
errors beyond the range."""


def _count_distribution(probabilities):
    """``P(K = j)``, ``j = 0..n``, for ``K`` a sum of independent Bernoulli(``probabilities``):
    one binomial per distinct probability (rows with the same error share theirs),
    convolved."""
    shares, repeats = np.unique(probabilities, return_counts=True)
    counts = np.ones(1)
    for p, m in zip(shares, repeats):
        counts = np.convolve(counts, stats.binom.pmf(np.arange(m + 1), m, p))
    return counts


def _at_least(probabilities, k):
    """``P(K >= k)`` for ``K`` a sum of independent Bernoulli(``probabilities``)."""
    return float(_count_distribution(probabilities)[k:].sum())


def beyond_range_test(value, sigma, study_range):
    """How far measured values reach beyond a range, and the p-value of that reach if
    every true value lay within it.

    Row ``i`` lies ``z_i = max(0, (x_i - hi) / s_i, (lo - x_i) / s_i)`` of its errors beyond
    the range. Whatever the true values inside the range, ``z_i`` is largest in
    distribution when the true value sits at an end: then ``P(z_i > c) = Phi(-c) +
    Phi(-c - w_i)`` (``w_i`` the range's width in errors), and a positive ``z_i`` is no
    larger in distribution than ``|N(0, 1)|``. Three statistics, each with its exact
    p-value at that least favourable truth, catch three ways of reaching beyond:

    * the sum ``T = sum z_i^2`` (many rows a little beyond): ``P(T >= t) <= sum_k P(K = k)
      P(chi2_k >= t)``, ``K`` the number of positive terms (a chi-bar-squared);
    * the number of rows more than ``BEYOND_COUNT_SIGMA`` errors beyond (some rows well
      beyond: true values spread past the range; the sum is swamped by the rows at the ends);
    * the largest ``z_i`` (one row far beyond).

    The p-value is three times the smallest of theirs (Bonferroni), so a table whose true
    values all lie within the range gets ``p < alpha`` in fewer than a share ``alpha`` of
    cases, wherever in the range they lie and whatever the table's size.

    Returns
    -------
    statistic : float
        ``T``.
    p_value : float
        The combined p-value (1 when no row lies beyond the range).
    """
    lo, hi = study_range
    value, sigma = np.asarray(value, float), np.asarray(sigma, float)
    z = np.maximum(0.0, np.maximum(value - hi, lo - value) / sigma)
    statistic = float(np.sum(z * z))
    if statistic == 0.0:
        return 0.0, 1.0
    width = (hi - lo) / sigma

    def beyond(c):
        return stats.norm.sf(c) + stats.norm.sf(c + width)

    counts = _count_distribution(beyond(0.0))
    k = np.arange(1, len(value) + 1)
    p_sum = float(np.sum(counts[1:] * stats.chi2.sf(statistic, k)))
    p_count = _at_least(beyond(BEYOND_COUNT_SIGMA), int((z > BEYOND_COUNT_SIGMA).sum()))
    p_max = float(-np.expm1(np.sum(np.log1p(-beyond(float(z.max()))))))
    return statistic, min(3.0 * min(p_sum, p_count, p_max), 1.0)


def prior_range(value, sigma, study_range, physical=(-math.inf, math.inf)):
    """The range of the flat prior of a measured input, and whether the data reject the
    study's.

    Parameters
    ----------
    value, sigma : ndarray
        The rows' measured values and their 1-sigma errors (SI).
    study_range : (float, float)
        The study's range of the input (its distribution's support).
    physical : (float, float)
        The input's physical range (``|b|`` below the reach of ball and bat, ...): a widened
        range never goes beyond it.

    Returns
    -------
    (lo, hi) : tuple of float
        The study's range, or, when the data reject it (``beyond_range_test`` below
        ``WIDEN_P_VALUE``), the range that best explains the measured values with
        ``lo <= study lo`` and ``hi >= study hi`` (the maximum likelihood of true values
        uniform over it, ``_range_log_likelihood``), within ``physical``.
    p_value : float
        The p-value of ``beyond_range_test`` (1 for an unbounded range).
    """
    lo, hi = study_range
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return (lo, hi), 1.0
    _, p_value = beyond_range_test(value, sigma, study_range)
    if p_value >= WIDEN_P_VALUE:
        return (lo, hi), p_value
    # The widened edges lie between the study's and the farthest measurement plus ten of
    # its errors (farther never helps), within the physical range.
    far_lo = max(physical[0], min(lo, float(np.min(value - 10 * sigma))))
    far_hi = min(physical[1], max(hi, float(np.max(value + 10 * sigma))))
    if far_lo >= lo and far_hi <= hi:
        return (lo, hi), p_value

    def cost(edges):
        return -_range_log_likelihood(value, sigma, edges[0], edges[1])

    x0 = [max(far_lo, min(lo, float(np.min(value)))), min(far_hi, max(hi, float(np.max(value))))]
    res = optimize.minimize(cost, x0, method="L-BFGS-B", bounds=[(far_lo, lo), (hi, far_hi)])
    return (float(res.x[0]), float(res.x[1])), p_value


def covering_range(value, sigma, study_range, physical=(-math.inf, math.inf)):
    """The study's range widened to cover every measured value and ``COVER_SIGMA`` of
    its errors, within ``physical`` (SI, as ``prior_range``)."""
    lo, hi = study_range
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return lo, hi
    lo = max(physical[0], min(lo, float(np.min(value - COVER_SIGMA * sigma))))
    hi = min(physical[1], max(hi, float(np.max(value + COVER_SIGMA * sigma))))
    return lo, hi


PRIOR_DEGREE = 8
"""Degree of the polynomial in the log-density of a measured input's prior
(``PriorFamily``). It must follow true values piled within 5 mm of both ends of a
drop test's +-1 in: with degree 4 such tables fitted ``e*`` and ``mu`` 0.18 and 0.24 of
their errors high over 400 tables, a misplaced prior; degree 8 removes that (shifts of
-0.15 and -0.24 on the same tables; degree 12 changes nothing more) and leaves tables
with spread-out true values as they were (shifts below 0.01)."""
PRIOR_RIDGE = 1e-2
"""Penalty ``ridge |alpha|^2 / 2`` on that polynomial's coefficients: it keeps them finite
when the data cannot fix one (true values piled at one end) and is negligible otherwise."""


class PriorFamily:
    """Densities of a measured input's true values over ``[lo, hi]`` whose logarithm is a
    polynomial of degree ``PRIOR_DEGREE`` (Legendre polynomials of the position in the
    range), plus, when the study's range ``inner`` lies within ``[lo, hi]``, a step beyond
    it: ``g(b) = exp(sum_j alpha_j P_j(t(b)) + alpha_s [b outside inner]) / N(alpha)``;
    ``alpha = 0`` is flat (Efron's g-modelling, Biometrika 103, 1 (2016)).

    A fit estimates ``alpha`` with the other parameters: a flat prior misplaces the true
    values of a table whose values pile up somewhere (at the ends of the range, say) and
    biases the fit, and a prior fixed beforehand from the measured inputs alone would
    leave its own uncertainty out of the intervals. The step lets the data say how many
    true values lie beyond the study's range, from none (``alpha_s`` far below 0, kept
    finite by ``PRIOR_RIDGE``: a share of about 1e-3 beyond) to as many as within.
    """

    def __init__(self, lo, hi, degree=PRIOR_DEGREE, inner=None):
        self.lo, self.hi, self.degree = lo, hi, degree
        inner_lo, inner_hi = inner if inner is not None else (lo, hi)
        self.inner = (max(lo, inner_lo), min(hi, inner_hi))
        self.step = self.inner[0] > lo or self.inner[1] < hi
        self.size = degree + int(self.step)
        """Number of coefficients (the polynomial's, and the step's when there is one)."""
        # Gauss-Legendre on each piece: the step makes the density jump at the study's ends.
        cuts = sorted({lo, *self.inner, hi})
        nodes, weights = [], []
        for a, b in zip(cuts[:-1], cuts[1:]):
            x, w = np.polynomial.legendre.leggauss(64)
            nodes.append(a + (b - a) * (x + 1) / 2)
            weights.append(w * (b - a) / 2)
        nodes = np.concatenate(nodes)
        self._basis_nodes = self.basis_at(nodes)
        self._node_weights = np.concatenate(weights)
        self._outside_nodes = (nodes < self.inner[0]) | (nodes > self.inner[1])

    def basis_at(self, b):
        """The basis functions at ``b`` (any shape): an array of shape ``b.shape + (size,)``."""
        t = 2 * (np.clip(b, self.lo, self.hi) - self.lo) / (self.hi - self.lo) - 1
        poly = np.polynomial.legendre.legvander(t, self.degree)[..., 1:]
        if not self.step:
            return poly
        outside = ((b < self.inner[0]) | (b > self.inner[1])).astype(float)
        return np.concatenate([poly, outside[..., None]], axis=-1)

    def log_norm(self, alpha, second=False):
        """``ln N(alpha)``, its gradient ``E_g[P_j]`` and, if ``second``, its Hessian
        ``Cov_g[P_j, P_l]``."""
        log_g = self._basis_nodes @ alpha
        top = log_g.max()
        w = self._node_weights * np.exp(log_g - top)
        total = w.sum()
        mean = (w @ self._basis_nodes) / total
        if not second:
            return top + math.log(total), mean
        cov = (self._basis_nodes.T * w) @ self._basis_nodes / total - np.outer(mean, mean)
        return top + math.log(total), mean, cov

    def density(self, b, alpha):
        """``g(b)`` (1 / the input's unit)."""
        return np.exp(self.basis_at(b) @ alpha - self.log_norm(alpha)[0])

    def share_outside(self, alpha):
        """The prior's probability beyond the study's range (0 without a step)."""
        if not self.step:
            return 0.0
        log_g = self._basis_nodes @ alpha
        w = self._node_weights * np.exp(log_g - log_g.max())
        return float(w[self._outside_nodes].sum() / w.sum())
