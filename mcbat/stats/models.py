"""What a fit solves: the model's draws for every row of a measurement table.

A fit compares each measured row with ``M`` draws of the model for that row. A *draw
model* builds those ``rows x M`` cases once (the study's nuisance scatter, the row's
measured inputs, their errors) and solves them at any value of the free parameters, so that
:class:`mcbat.stats.fit.Likelihood` never needs to know which kernel it is fitting:

* :class:`BatFrameModel`: a ball moving across a bat onto its axis, in the bat frame (a
  drop test: ``studies/cross_nathan_2006.toml``); the table gives each row's impact
  parameter (and incoming spin), the observables are ``exit_speed`` (m/s),
  ``scattering_angle`` (deg) and ``spin_out`` (rad/s, about the bat axis).
* :class:`GameModel`: a game study (a pitch and a swing in the field frame); the table
  gives what a tracking system reports, in Statcast's names and units: ``launch_speed``
  (mph), ``launch_angle`` and ``spray_angle`` (deg), ``spin_rate``, ``backspin`` and
  ``sidespin`` (rpm); optionally each row's measured swing and pitch (``bat_speed`` and
  ``pitch_speed`` in mph, ``attack_angle`` in deg, ``undercut`` and ``from_barrel_end``
  in m). Inputs the table does not give are drawn from the study.

Measured inputs with an ``_err`` column are drawn from their posterior given the
measurement: the prior of the true values times a normal of that width about the measured
value, over a bounded range. The draws come from the posterior under a flat prior over that
range; the mixture likelihood of :mod:`mcbat.stats.fit` reweights them to a prior it
estimates with the parameters (:class:`PriorFamily`), so that a table whose true values
pile up somewhere (at the ends of the range, say) is not fitted as if they were spread
evenly. The draws are *stratified*: draw ``k`` of a row lies in the ``k``-th of ``M``
equal-probability slices of that posterior for the first such input (the slices of any
further one are shuffled, as in a Latin hypercube). The order matters:
:func:`mcbat.stats.fit.draw_moments` pairs neighbouring slices to measure the Monte Carlo
error of the mean.

The range a measured input's true values are marginalised over depends on
``input_prior``:

* ``"cover"`` (what the mixture likelihood uses by default): the study's range widened to
  cover every measured value and :data:`COVER_SIGMA` of its errors (never beyond the
  input's physical range). The estimated prior has a step at each end of the study's
  range (:class:`PriorFamily`), fitted with the rest: a table whose true values stay
  within the study's range fits the step far down (the study's range, in effect), one
  whose true values reach beyond fits it up, and nothing is truncated.
* ``"widen"`` (the normal likelihood's default): the study's range, unless the measured
  values reject it (:func:`beyond_range_test`, :func:`prior_range`): then the range that
  best explains them (the study's range widened, never narrowed, never beyond the
  physical range).
* ``"study"``: the study's range, and a table whose measured values reject it is refused.

Truncating each row's true value to a range the data reach beyond would bias the fit
without a word (rows measured 2-3 errors beyond the edge forced onto it). Every fit
reports the range it used (:attr:`_DrawModel.priors`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize, stats

from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.geometry import angles_from_impact_parameters, ball_centre_radial_distance
from mcbat.core.status import OK
from mcbat.core.swing import (
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    allocate_game_outputs,
    solve_game_batch,
)
from mcbat.dataset.schema import derive, derive_game
from mcbat.errors import InputError

__all__ = ["BAT_FRAME_COLUMNS", "COVER_SIGMA", "BatFrameModel", "DrawModel",
           "GAME_TABLE_COLUMNS", "GAME_WRITTEN", "GameModel", "INPUT_PRIORS", "OUTLIER_SIGMA",
           "PRIOR_DEGREE", "PriorFamily", "WIDEN_P_VALUE", "beyond_range_test",
           "covering_range", "draw_model", "prior_range", "solve_game_inputs", "solve_study",
           "table_columns"]

OUTLIER_SIGMA = 8.0
"""A measured value further than this many sigma beyond every model prediction over the
search ranges is refused (a typo or a wrong unit), not fitted; likewise a measured input
this many of its errors outside the study's range."""
GRAZING = 0.999
"""A measured ``|b|`` at or above this fraction of the reach ``R + r`` (a contact angle
above 87.4 deg) is refused: the ball grazes the bat."""
INPUT_PRIORS = ("cover", "widen", "study")
"""The ranges a measured input's true values are marginalised over (module docstring)."""
COVER_SIGMA = 5.0
"""With ``input_prior = "cover"`` the range reaches this many errors beyond every measured
value (the posterior of a row's true value beyond it is below 3e-7 of the whole)."""
WIDEN_P_VALUE = 0.01
"""The measured values of an input reject the study's range when :func:`beyond_range_test`
gives a p-value below this: when every true value does lie within the study's range, that
happens in fewer than 1 % of tables, whatever their size and wherever in the range the
true values lie (the test is computed at the least favourable place, the range's ends; for
true values spread over the range, far more rarely). A rejection that is wrong costs
little (the fit marginalises over a wider range, with the prior's shape estimated), one
that is missed truncates the true values and biases the fit."""
_MPH = 0.44704
_DEG = math.pi / 180.0

BAT_FRAME_COLUMNS = {
    # name: (unit, role); role "input" columns are measured inputs, "observable" are fitted
    "impact_parameter": ("m", "input"),
    "spin_in": ("rad/s", "input"),
    "exit_speed": ("m/s", "observable"),
    "scattering_angle": ("deg", "observable"),
    "spin_out": ("rad/s", "observable"),
}
"""Columns of a bat-frame measurement table (a drop test), with their units."""
GAME_TABLE_COLUMNS = {
    "pitch_speed": ("mph", "input"),
    "bat_speed": ("mph", "input"),
    "attack_angle": ("deg", "input"),
    "undercut": ("m", "input"),
    "from_barrel_end": ("m", "input"),
    "launch_speed": ("mph", "observable"),
    "launch_angle": ("deg", "observable"),
    "spray_angle": ("deg", "observable"),
    "spin_rate": ("rpm", "observable"),
    "backspin": ("rpm", "observable"),
    "sidespin": ("rpm", "observable"),
}
"""Columns of a game measurement table (Statcast's names and units where it has them)."""

UNITS_HINT = {
    "exit_speed": "wrong unit? exit_speed is in m/s (mph would be 2.24 times larger, km/h "
                  "3.6 times)",
    "scattering_angle": "wrong unit? scattering_angle is in degrees (radians would be 57 "
                        "times smaller)",
    "spin_out": "wrong unit or sign convention? spin_out is in rad/s about the bat axis (rpm "
                "would be 9.55 times larger)",
    "launch_speed": "wrong unit? launch_speed is in mph (m/s would be 2.24 times smaller, "
                    "km/h 1.6 times larger)",
    "launch_angle": "wrong unit or convention? launch_angle is the elevation in degrees",
    "spray_angle": "wrong unit or convention? spray_angle is in degrees, positive towards "
                   "right field (docs/batting.md)",
    "spin_rate": "wrong unit? spin_rate is in rpm (rad/s would be 9.55 times smaller)",
    "backspin": "wrong unit or sign? backspin is in rpm, positive for backspin",
    "sidespin": "wrong unit or sign? sidespin is in rpm (docs/batting.md)",
    "hit_distance_sc": "wrong unit? hit_distance_sc is in ft (m would be 3.28 times smaller)",
}
"""What to check when a column lies far outside anything the model gives."""


def table_columns(game: bool) -> dict:
    """The measurement columns of a game (True) or a bat-frame (False) study."""
    return GAME_TABLE_COLUMNS if game else BAT_FRAME_COLUMNS


def draw_model(study, table, draws, seed, fixed=None, input_prior=None, likelihood=None):
    """The draw model of ``study`` (:class:`GameModel` or :class:`BatFrameModel`);
    ``draws`` None: the model's :attr:`DEFAULT_DRAWS`; ``input_prior`` None: ``"cover"``
    for the mixture likelihood (``likelihood``, default the model's), which estimates the
    prior, else ``"widen"``."""
    if input_prior is not None and input_prior not in INPUT_PRIORS:
        raise InputError("input_prior", f"must be one of {', '.join(INPUT_PRIORS)}, got "
                         f"{input_prior!r}")
    kind = getattr(study, "kind", None)
    form = likelihood or (GameModel if kind == "game" else BatFrameModel).LIKELIHOOD
    if input_prior is None:
        input_prior = "cover" if form == "mixture" else "widen"
    elif input_prior == "cover" and form != "mixture":
        raise InputError("input_prior", "'cover' needs the mixture likelihood (the normal "
                         "one cannot estimate the prior's step at the study's range)")
    if kind == "flight":
        from mcbat.stats.flight_model import FlightModel  # it builds on this module

        # A flight table has no measured inputs with errors: no prior to choose.
        return FlightModel(study, table, FlightModel.DEFAULT_DRAWS if draws is None else draws,
                           seed, fixed)
    cls = GameModel if kind == "game" else BatFrameModel
    return cls(study, table, cls.DEFAULT_DRAWS if draws is None else draws, seed, fixed,
               input_prior)


def _range_log_likelihood(value, sigma, lo, hi):
    """``sum_i ln p(x_i)`` of measured values ``x_i +- sigma_i`` whose true values are
    uniform over ``[lo, hi]``: ``p(x) = (Phi((hi - x)/s) - Phi((lo - x)/s)) / (hi - lo)``."""
    mass = stats.norm.cdf((hi - value) / sigma) - stats.norm.cdf((lo - value) / sigma)
    return float(np.sum(np.log(np.maximum(mass, 1e-300))) - len(value) * math.log(hi - lo))


BEYOND_COUNT_SIGMA = 2.0
"""The count statistic of :func:`beyond_range_test` counts rows more than this many of their
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
    * the number of rows more than :data:`BEYOND_COUNT_SIGMA` errors beyond (some rows well
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
        The study's range, or, when the data reject it (:func:`beyond_range_test` below
        :data:`WIDEN_P_VALUE`), the range that best explains the measured values with
        ``lo <= study lo`` and ``hi >= study hi`` (the maximum likelihood of true values
        uniform over it, :func:`_range_log_likelihood`), within ``physical``.
    p_value : float
        The p-value of :func:`beyond_range_test` (1 for an unbounded range).
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
    """The study's range widened to cover every measured value and :data:`COVER_SIGMA` of
    its errors, within ``physical`` (SI, as :func:`prior_range`)."""
    lo, hi = study_range
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return lo, hi
    lo = max(physical[0], min(lo, float(np.min(value - COVER_SIGMA * sigma))))
    hi = min(physical[1], max(hi, float(np.max(value + COVER_SIGMA * sigma))))
    return lo, hi


PILOT_POINTS = 61
"""Values of a measured impact parameter a row's pilot scan solves (:meth:`BatFrameModel.
refine_draws`), evenly over +-:data:`PILOT_SIGMA` of its errors."""
PILOT_SIGMA = 6.0


PRIOR_DEGREE = 4
"""Degree of the polynomial in the log-density of a measured input's prior
(:class:`PriorFamily`)."""
PRIOR_RIDGE = 1e-2
"""Penalty ``ridge |alpha|^2 / 2`` on that polynomial's coefficients: it keeps them finite
when the data cannot fix one (true values piled at one end) and is negligible otherwise."""


class PriorFamily:
    """Densities of a measured input's true values over ``[lo, hi]`` whose logarithm is a
    polynomial of degree :data:`PRIOR_DEGREE` (Legendre polynomials of the position in the
    range), plus, when the study's range ``inner`` lies within ``[lo, hi]``, a step beyond
    it: ``g(b) = exp(sum_j alpha_j P_j(t(b)) + alpha_s [b outside inner]) / N(alpha)``;
    ``alpha = 0`` is flat (Efron's g-modelling, Biometrika 103, 1 (2016)).

    A fit estimates ``alpha`` with the other parameters: a flat prior misplaces the true
    values of a table whose values pile up somewhere (at the ends of the range, say) and
    biases the fit, and a prior fixed beforehand from the measured inputs alone would
    leave its own uncertainty out of the intervals. The step lets the data say how many
    true values lie beyond the study's range, from none (``alpha_s`` far below 0, kept
    finite by :data:`PRIOR_RIDGE`: a share of about 1e-3 beyond) to as many as within.
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


def rows_text(mask, values=None, limit=5):
    """``"rows 3, 7 (value ...)"``: the 1-based rows where ``mask`` holds."""
    idx = np.flatnonzero(mask)
    shown = ", ".join(str(i + 1) + (f" ({values[i]:.6g})" if values is not None else "")
                      for i in idx[:limit])
    more = f" and {len(idx) - limit} more" if len(idx) > limit else ""
    return f"row{'s' if len(idx) > 1 else ''} {shown}{more}"


class _DrawModel:
    """Shared bookkeeping: the table's columns checked against the model's, the measured
    inputs drawn, the free parameters written into the input array."""

    COLUMNS: dict = {}
    PARAMETERS: dict = {}
    """Fit parameter -> row of the input array it sets."""
    KIND = ""
    FAILURE_HINTS: dict = {}
    DEFAULT_DRAWS = 48
    """Draws per row unless the user asks for another number."""
    LIKELIHOOD = "gaussian"
    """The form of a row's likelihood unless the user asks for another
    (:mod:`mcbat.stats.fit`): a normal of the draws' mean and covariance."""
    SEARCH: dict = {}
    """Search ranges of the fit's coarse grid that differ from the default
    (:data:`mcbat.stats.fit.SEARCH`)."""

    def __init__(self, study, table, draws, seed, fixed, input_prior="cover"):
        self.source = table.attrs.get("source")
        self.study = study
        self.rows = len(table)
        self.draws = draws
        self.input_prior = input_prior
        self.priors = {}
        """Measured input -> the range its draws cover: ``study_range`` and ``range``
        (table units), ``widened`` (the two differ), and whether the measured values reject
        the study's range (``rejects_study_range``, with the ``p_value`` of
        :func:`beyond_range_test`)."""
        self.prior_draws = {}
        """Measured input over a bounded range -> ``(draws (rows x M), lo, hi)`` in table
        units: its draws, taken from the posterior under a flat prior over ``[lo, hi]``,
        which a likelihood may reweight to another prior (:mod:`mcbat.stats.fit`)."""
        self._stratified = False
        self.smeared = {}
        """Measured input over a bounded range -> ``(value, sigma, lo, hi, scale)`` (SI)."""
        self.draw_log_weight = None
        """Importance weights (log, rows x M) of the draws, once :meth:`refine_draws` has
        drawn some of them near each row's posterior; None: every draw weighs the same."""
        self.plain_draws = draws
        """The first ``plain_draws`` draws of a row come from the posterior of its measured
        inputs given their measurement alone (its mean and covariance estimate the row's
        predictions); after :meth:`refine_draws`, the rest lie near the posterior given the
        observables too."""
        known = {c for c in self.COLUMNS} | {f"{c}_err" for c in self.COLUMNS}
        for col in table.columns:
            if col not in known:
                base = col[:-4] if col.endswith("_err") else col
                what = "an uncertainty of " if col.endswith("_err") else ""
                raise InputError(col, f"a {self.KIND} study's model cannot use {what}"
                                 f"{base!r} (its columns: {', '.join(self.COLUMNS)}, each "
                                 f"optionally with an _err column)", self.source)
        self.observables = [c for c, (_, role) in self.COLUMNS.items()
                            if role == "observable" and c in table.columns]
        if not self.observables:
            names = [c for c, (_, role) in self.COLUMNS.items() if role == "observable"]
            raise InputError(None, f"the table has none of the observables of a "
                             f"{self.KIND} study: {', '.join(names)}", self.source)
        for name in fixed or {}:
            if name not in self.PARAMETERS:
                raise InputError("fixed", f"unknown parameter {name!r} for a {self.KIND} "
                                 f"study (choose from {', '.join(self.PARAMETERS)})")
        self.rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 13,)))

    def measured_draws(self, name, table, support, scale=1.0, physical=(-math.inf, math.inf),
                       key=None):
        """Per-draw values (SI: the table's value times ``scale``) of measured input
        ``name``: its value repeated, or smeared by its ``_err`` (module docstring) over
        the range of :meth:`prior`; ``physical`` is the input's physical range and ``key``
        the study's name of the input (for messages)."""
        value = table[name].to_numpy(float) * scale
        if f"{name}_err" not in table.columns:
            return np.repeat(value, self.draws)
        sigma = table[f"{name}_err"].to_numpy(float) * scale
        lo, hi = self.prior(name, value, sigma, support, physical, scale, key)
        slices = np.tile(np.arange(self.draws), (self.rows, 1))
        if self._stratified:  # a further smeared input: its slices shuffled per row
            slices = self.rng.permuted(slices, axis=1)
        self._stratified = True
        u = (slices + self.rng.uniform(size=slices.shape)) / self.draws
        a = ((lo - value) / sigma)[:, None]
        b = ((hi - value) / sigma)[:, None]
        far = (a > OUTLIER_SIGMA).ravel() | (b < -OUTLIER_SIGMA).ravel()
        if far.any():
            where = "the study's" if not self.priors[name]["widened"] else "the widened"
            raise InputError(name, f"{rows_text(far, value / scale)}: more than "
                             f"{OUTLIER_SIGMA:g} of its errors outside {where} range "
                             f"{lo / scale:g}..{hi / scale:g} (the physical range ends there: "
                             f"a typo or another unit?)", self.source)
        if math.isinf(lo) and math.isinf(hi):
            z = stats.norm.ppf(u)
        else:
            z = stats.truncnorm.ppf(u, a, b)
        draws = value[:, None] + sigma[:, None] * z
        if math.isfinite(lo) and math.isfinite(hi):
            self.prior_draws[name] = (draws / scale, lo / scale, hi / scale)
            self.smeared[name] = (value, sigma, lo, hi, scale)
        return draws.ravel()

    def prior(self, name, value, sigma, support, physical, scale, key):
        """The flat prior's range (SI) of measured input ``name`` (module docstring),
        recorded in :attr:`priors`; :class:`InputError` when the data reject the study's
        range and ``input_prior`` is ``"study"``."""
        (lo, hi), p_value = prior_range(value, sigma, support, physical)
        rejected = p_value < WIDEN_P_VALUE
        if rejected and self.input_prior == "study":
            beyond = (value < support[0] - 2 * sigma) | (value > support[1] + 2 * sigma)
            rows = (f"{rows_text(beyond, value / scale)} lie more than 2 of their errors "
                    if beyond.any() else "the measured values lie ")
            raise InputError(name, f"{rows}outside the study's range {support[0] / scale:g}.."
                             f"{support[1] / scale:g}, which the data reject (p = "
                             f"{p_value:.2g} < {WIDEN_P_VALUE:g} if every true value lay "
                             f"within it): widen {key or name} in the study, or let the fit "
                             f"marginalise beyond it (--input-prior cover)", self.source)
        if self.input_prior == "cover":
            lo, hi = covering_range(value, sigma, support, physical)
        elif not rejected:
            lo, hi = support
        self.priors[name] = {"study_range": [support[0] / scale, support[1] / scale],
                             "range": [lo / scale, hi / scale],
                             "widened": bool(lo < support[0] or hi > support[1]),
                             "rejects_study_range": bool(rejected), "p_value": p_value}
        return lo, hi

    def support(self, key):
        """The study's range of input ``key`` (unbounded when it is not drawn)."""
        dist = self.study.inputs.get(key)
        if dist is None or getattr(dist, "family", None) == "fixed":
            return -math.inf, math.inf
        return dist.support()

    def record_study_values(self):
        """Keep the study's own value of every parameter (the mean over the draws) in
        :attr:`study_values`, before a fit changes them."""
        self.study_values = {name: float(np.mean(self.inputs[row]))
                             for name, row in self.PARAMETERS.items()}

    def set_parameters(self, values):
        """Write ``{parameter: value}`` into every draw."""
        for name, value in values.items():
            self.inputs[self.PARAMETERS[name]] = value


DrawModel = _DrawModel
"""The base of a draw model, for models defined outside this module
(:class:`mcbat.stats.flight_model.FlightModel`)."""


class BatFrameModel(_DrawModel):
    """The bat-frame kernel (:func:`mcbat.core.batch.solve_batch`) on a drop-test table.

    The study must place the contact by ``contact.impact_parameter``; each row's measured
    impact parameter sets the contact angle of its draws (about the study's approach
    azimuth of each draw), a measured ``spin_in`` the incoming spin about the bat axis.
    """

    COLUMNS = BAT_FRAME_COLUMNS
    KIND = "bat-frame"
    LIKELIHOOD = "mixture"  # the draws vary mainly in the stratified measured inputs
    PARAMETERS = {name: INPUT_FIELDS.index(name)
                  for name in ("e", "mu", "ball_inertia_factor", "axial", "e_x")}
    FAILURE_HINTS = {"not_approaching": ("impact_parameter", " (the ball does not approach "
                                         "the bat at the contact: an impact parameter at the "
                                         "reach of ball and bat?)")}

    def __init__(self, study, table, draws, seed, fixed=None, input_prior="cover"):
        super().__init__(study, table, draws, seed, fixed, input_prior)
        source, rows = self.source, self.rows
        if "contact.impact_parameter" not in study.inputs:
            raise InputError("impact_parameter", f"study {study.name!r} places the contact by "
                             f"contact.angle, not contact.impact_parameter: a measured impact "
                             f"parameter needs a study of a ball moving across the bat onto "
                             f"its axis (as studies/cross_nathan_2006.toml)", source)
        if "impact_parameter" not in table.columns:
            raise InputError("impact_parameter", "missing required column", source)
        index = {name: i for i, name in enumerate(INPUT_FIELDS)}
        cols = study.sample(0, rows * draws, seed)
        inputs = np.stack([np.asarray(cols[n], np.float64) for n in INPUT_FIELDS])
        b_meas = table["impact_parameter"].to_numpy(float)
        n = rows * draws
        ball_r = inputs[index["ball_radius"]]
        radius, slope = inputs[index["bat_radius"]], inputs[index["bat_slope"]]
        reach = np.array([ball_centre_radial_distance(*v) for v in zip(ball_r, radius, slope)])
        edge = GRAZING * reach.min()
        b = self.measured_draws("impact_parameter", table,
                                study.inputs["contact.impact_parameter"].support(),
                                physical=(-edge, edge), key="contact.impact_parameter")
        # The study's approach azimuth of each draw, then the contact angle of the row's b.
        angle0 = np.empty(n)
        angles_from_impact_parameters(np.asarray(cols["impact_parameter"], float), ball_r,
                                      radius, slope, np.zeros(n), angle0)
        azimuth = inputs[index["angle"]] - angle0
        angles_from_impact_parameters(b, ball_r, radius, slope, azimuth,
                                      inputs[index["angle"]])
        self._geometry = (ball_r, radius, slope, azimuth)
        grazing = (np.abs(b_meas) >= GRAZING * reach.reshape(rows, draws).min(axis=1))
        if grazing.any():
            raise InputError("impact_parameter", f"{rows_text(grazing, b_meas)}: at the reach "
                             f"of ball and bat ({reach.min():.5g} m): a grazing contact, not a "
                             f"measurable impact", source)
        missed = np.isnan(inputs[index["angle"]]).reshape(rows, draws).all(axis=1)
        if missed.any():
            raise InputError("impact_parameter", f"{rows_text(missed, b_meas)}: beyond the "
                             f"reach of ball and bat (the ball would miss)", source)
        if "spin_in" in table.columns:
            inputs[index["ball_wz_in"]] = self.measured_draws("spin_in", table,
                                                              (-math.inf, math.inf))
        self.inputs = inputs
        self.record_study_values()
        self.set_parameters(fixed or {})  # e.g. e_x = 0: the rigid model
        self._axial = inputs[index["axial"]].copy()
        self._out = allocate_outputs(n)

    def set_parameters(self, values):
        """As the base class; ``axial`` shifts the study's impact points (keeping their
        scatter) instead of replacing them."""
        for name, value in values.items():
            if name == "axial":
                self.inputs[self.PARAMETERS[name]] = self._axial + value
            else:
                self.inputs[self.PARAMETERS[name]] = value

    def refine_draws(self, y, s2, observables):
        """Move half of each row's draws of the measured impact parameter next to its
        posterior given the observables, at the current parameters; returns whether it did.

        The draws from the posterior given the measured ``b`` alone (stratified, 5 mm wide
        in a drop test) resolve badly what the observables say: the scattering angle alone
        fixes ``b`` to about a millimetre, so a row measured three errors from its true
        ``b`` had one draw or none near it, and the likelihood of ``mu`` moved by up to four
        of its errors between 48 and 384 draws. Here a pilot scan of ``b`` (61 values over
        +-6 errors, the row's first draw otherwise) finds the posterior's mean and spread;
        the second half of the draws is stratified over a truncated normal there, twice as
        wide, and every draw is weighted by the ratio of the measurement's posterior to the
        two halves' mixture (defensive importance sampling: Hesterberg, Technometrics 37,
        185 (1995)), so the likelihood stays the same integral, better resolved.

        Parameters
        ----------
        y, s2 : ndarray, (rows, observables)
            The measured observables and their variances.
        observables : list of str
            Their names (:attr:`observables`).
        """
        if "impact_parameter" not in self.smeared or self.draws < 4:
            return False
        value, sigma, lo, hi, _ = self.smeared["impact_parameter"]
        rows, draws, points = self.rows, self.draws, PILOT_POINTS
        index = {name: i for i, name in enumerate(INPUT_FIELDS)}
        first = np.arange(rows) * draws
        z = np.linspace(-PILOT_SIGMA, PILOT_SIGMA, points)
        b_grid = np.clip(value[:, None] + sigma[:, None] * z, lo, hi)
        pilot = np.repeat(self.inputs[:, first], points, axis=1)
        ball_r, radius, slope, azimuth = (np.repeat(g[first], points) for g in self._geometry)
        angles_from_impact_parameters(b_grid.ravel(), ball_r, radius, slope, azimuth,
                                      pilot[index["angle"]])
        values, status = self._solve(pilot, allocate_outputs(rows * points))
        f = np.stack([values[c].reshape(rows, points) for c in observables], axis=2)
        log_post = (-0.5 * ((y[:, None, :] - f) ** 2 / s2[:, None, :]).sum(axis=2)
                    - 0.5 * ((b_grid - value[:, None]) / sigma[:, None]) ** 2)
        log_post = np.where((status == OK).reshape(rows, points) & np.isfinite(log_post),
                            log_post, -np.inf)
        if not np.isfinite(log_post).any(axis=1).all():
            return False
        p = np.exp(log_post - log_post.max(axis=1, keepdims=True))
        p /= p.sum(axis=1, keepdims=True)
        centre = (p * b_grid).sum(axis=1)
        spread = np.sqrt((p * (b_grid - centre[:, None]) ** 2).sum(axis=1))
        width = np.maximum(2.0 * spread, 2.0 * PILOT_SIGMA / (points - 1) * sigma)
        plain = draws // 2
        strata = [np.arange(plain), np.arange(draws - plain)]
        u = [(k + self.rng.uniform(size=(rows, len(k)))) / len(k) for k in strata]
        posterior = stats.truncnorm(((lo - value) / sigma)[:, None],
                                    ((hi - value) / sigma)[:, None],
                                    loc=value[:, None], scale=sigma[:, None])
        near = stats.truncnorm(((lo - centre) / width)[:, None], ((hi - centre) / width)[:, None],
                               loc=centre[:, None], scale=width[:, None])
        b = np.concatenate([posterior.ppf(u[0]), near.ppf(u[1])], axis=1)
        share = plain / draws
        log_q = np.logaddexp(math.log(share) + posterior.logpdf(b),
                             math.log(1.0 - share) + near.logpdf(b))
        self.draw_log_weight = posterior.logpdf(b) - log_q
        self.plain_draws = plain
        angles_from_impact_parameters(b.ravel(), *self._geometry, self.inputs[index["angle"]])
        scale = self.smeared["impact_parameter"][4]
        self.prior_draws["impact_parameter"] = (b / scale, lo / scale, hi / scale)
        return True

    def solve(self):
        """Solve every draw: ``{observable: float64[rows * draws]}`` and the status."""
        return self._solve(self.inputs, self._out)

    def _solve(self, inputs, buffers):
        solver = self.study.solver
        out, status, end = buffers
        solve_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"],
                    out, status, end)
        o = {name: out[i] for i, name in enumerate(OUTPUT_FIELDS)}
        derived = derive([o[f"ball_v{c}"] for c in "xyz"], [o[f"ball_w{c}"] for c in "xyz"])
        values = {"exit_speed": derived["exit_speed"],
                  "scattering_angle": derived["scattering_angle"],
                  "spin_out": derived["spin_axial"]}
        return {c: values[c] for c in self.observables}, status


class GameModel(_DrawModel):
    """The game kernel (:func:`mcbat.core.swing.solve_game_batch`) on a tracking table.

    Each row's measured pitch and swing (any of ``pitch_speed``, ``bat_speed``,
    ``attack_angle``, ``undercut``, ``from_barrel_end``) replace the study's draws of
    them; the rest of the study's scatter is nuisance. Parameters: ``e`` (the game
    restitution's ``e*`` at its reference speed, ``e_ref``), ``mu`` and ``e_x``.
    """

    COLUMNS = GAME_TABLE_COLUMNS
    KIND = "game"
    PARAMETERS = {"e": GAME_INPUT_FIELDS.index("e_ref"), "mu": GAME_INPUT_FIELDS.index("mu"),
                  "e_x": GAME_INPUT_FIELDS.index("e_x")}
    MEASURED = {"pitch_speed": ("pitch.speed", _MPH), "bat_speed": ("swing.bat_speed", _MPH),
                "attack_angle": ("swing.attack_angle", _DEG),
                "undercut": ("contact.undercut", 1.0),
                "from_barrel_end": ("contact.from_barrel_end", 1.0)}
    DEFAULT_DRAWS = 128
    """A game's nuisance scatter (impact point, bat angles, ...) is drawn independently,
    so the covariance of a row's 4 observables is estimated from its draws with noise, and
    the inverse of a noisy covariance is too large on average (by ``~(d + 1)/M``): with 48
    draws chi2/dof came out 1.11 on a 1000-row table, 1.03 with 192, so the likelihood was
    ~10 % too sharp. 128 draws leave ~4 %. (A drop test's spread is dominated by its
    stratified impact parameter or by the measurement errors: chi2/dof 0.98-1.01 at 48.)"""
    SEARCH = {"e": (0.2, 0.8)}
    """A baseball's e* at game speeds lies well within 0.2-0.8 (the game preset: 0.555 at
    85 ft/s, docs/batting.md): the coarse grid covers that range, so launch speeds in another
    unit (which would need e* near 0.07 for m/s or 0.96 for km/h) are refused with a hint
    instead of fitted."""
    FAILURE_HINTS = {"not_approaching": ("undercut", " (the ball misses or does not meet the "
                                         "bat: an undercut beyond the reach of ball and "
                                         "barrel?)")}

    def __init__(self, study, table, draws, seed, fixed=None, input_prior="cover"):
        super().__init__(study, table, draws, seed, fixed, input_prior)
        inputs = study.sample_inputs(0, self.rows * draws, seed)
        cols = {name: inputs[i] for i, name in enumerate(GAME_INPUT_FIELDS)}
        reach = float(np.max(cols["ball_radius"] + cols["bat_radius"]))
        physical = {"pitch_speed": (0.0, math.inf), "bat_speed": (0.0, math.inf),
                    "attack_angle": (-0.5 * math.pi, 0.5 * math.pi),
                    "undercut": (-reach, reach),
                    "from_barrel_end": (0.0, float(np.min(cols["bat_length"])))}
        for name, (key, scale) in self.MEASURED.items():
            if name in table.columns:
                cols[name][:] = self.measured_draws(name, table, self.support(key), scale,
                                                    physical[name], key)
        if "from_barrel_end" in table.columns:
            study.fill_contact(cols)
        self.inputs = inputs
        self.record_study_values()
        self.set_parameters(fixed or {})
        self._out = allocate_game_outputs(self.rows * draws)

    def solve(self):
        """Solve every draw: ``{observable: float64[rows * draws]}`` (table units) and the
        status."""
        solver = self.study.solver
        frame, out, game_out, status, end = self._out
        solve_game_batch(self.inputs, solver["steps"], solver["tolerance"],
                         solver["max_steps"], frame, out, game_out, status, end)
        g = {name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)}
        batted = derive_game([g[f"field_ball_v{c}"] for c in "xyz"],
                             [g[f"field_ball_w{c}"] for c in "xyz"])
        return {c: batted[c] for c in self.observables}, status


GAME_WRITTEN = ("pitch_speed", "bat_speed", "attack_angle", "undercut")
"""The measured inputs :func:`mcbat.stats.measurements.synthesize` writes into a game
table."""


def solve_study(study, rows, seed, params):
    """Solve the study's first ``rows`` samples (seed ``seed``) with ``params`` (``{"e": ...,
    "mu": ..., "e_x": ...}``, None: the study's) overriding its values.

    Returns
    -------
    measured, observed : dict of str -> ndarray
        The measured inputs a table of this kind carries and its observables, in the
        table's units (:data:`BAT_FRAME_COLUMNS`, :data:`GAME_TABLE_COLUMNS`).
    ok : ndarray of bool
        Rows whose impact was solved.
    """
    if getattr(study, "kind", None) == "game":
        return _solve_game(study, rows, seed, params)
    return _solve_drop_test(study, rows, seed, params)


def _solve_drop_test(study, rows, seed, params):
    """A drop test's true inputs (table units), observables and good rows."""
    cols = study.sample(0, rows, seed)
    for name, value in params.items():
        if value is not None:
            cols[name] = np.full(rows, float(value))
    inputs = np.stack([np.asarray(cols[name], np.float64) for name in INPUT_FIELDS])
    out, status, end = allocate_outputs(rows)
    solver = study.solver
    solve_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"], out, status,
                end)
    o = {name: out[i] for i, name in enumerate(OUTPUT_FIELDS)}
    derived = derive([o[f"ball_v{c}"] for c in "xyz"], [o[f"ball_w{c}"] for c in "xyz"])
    measured = {"impact_parameter": cols["impact_parameter"], "spin_in": cols["ball_wz_in"]}
    observed = {"exit_speed": derived["exit_speed"],
                "scattering_angle": derived["scattering_angle"],
                "spin_out": derived["spin_axial"]}
    return measured, observed, status == 0


def _solve_game(study, rows, seed, params):
    """A game's true measured inputs (table units), batted balls and good rows."""
    inputs = study.sample_inputs(0, rows, seed)
    cols = {name: inputs[i] for i, name in enumerate(GAME_INPUT_FIELDS)}
    for name, value in params.items():
        if value is not None:
            inputs[GameModel.PARAMETERS[name]] = value
    batted, ok = solve_game_inputs(study, inputs)
    measured = {name: cols[name].copy() / GameModel.MEASURED[name][1] for name in GAME_WRITTEN}
    observed = {name: batted[name] for name in ("launch_speed", "launch_angle", "spray_angle",
                                                "spin_rate")}
    return measured, observed, ok


def solve_game_inputs(study, inputs):
    """Solve a game kernel's input rows (:data:`mcbat.core.swing.GAME_INPUT_FIELDS` x n)
    with the study's solver settings: the batted balls' Statcast outputs
    (:func:`mcbat.dataset.schema.derive_game`) and which rows were solved."""
    n = inputs.shape[1]
    frame, out, game_out, status, end = allocate_game_outputs(n)
    solver = study.solver
    solve_game_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"], frame,
                     out, game_out, status, end)
    g = {name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)}
    batted = derive_game([g[f"field_ball_v{c}"] for c in "xyz"],
                         [g[f"field_ball_w{c}"] for c in "xyz"])
    return batted, status == 0
