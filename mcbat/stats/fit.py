"""Fit model parameters to a measurement table, marginalising nuisance scatter and the
errors of the measured inputs.

Likelihood. Row ``i`` of the table has measured inputs (a drop test's impact parameter
``b_i`` and incoming spin; a game's bat speed, attack angle, undercut, ...) and measured
observables ``y_i`` (exit speed, scattering angle, outgoing spin; or launch speed, launch
angle, spin rate, ...) with 1-sigma errors ``s_i`` (the ``_err`` columns; an observable
without one gets one error for all rows, :func:`default_errors`). For each row, ``M`` draws
are solved with the fast kernel at parameters ``theta`` (:mod:`mcbat.stats.models` builds
them):

* the study's nuisance scatter (the impact point, the spread of the incoming spin when
  the table has no ``spin_in``, ...) is drawn from the study;
* a measured input with an ``_err`` column is drawn from its posterior given the
  measurement (a prior of the true values estimated from the table, times a normal of the
  stated width about the measured value, within the range the study allows for that
  input: :mod:`mcbat.stats.models`), stratified over the ``M`` draws (one draw in each of
  ``M`` equal-probability slices) so that the smear is represented with little Monte Carlo
  noise; without an ``_err`` column the input is exact. With the mixture likelihood, half
  of a drop test's draws are then moved near each row's posterior given the observables
  too, with importance weights (:meth:`Likelihood.refine`): the observables fix a row's
  true impact parameter far better than its measurement does.

Draws whose impact fails (status not ``ok``, e.g. a nuisance geometry in which the ball does
not reach the bat) are dropped: the measured rows are impacts. The ``n_i`` good draws
``f_ik(theta)`` of row ``i`` stand for the distribution of its true observables, and the
likelihood takes one of two forms (``likelihood``):

* ``"mixture"``: the marginal likelihood itself, the draws' average of the measurement's
  density,

      L_i = (1 / n_i) sum_k N(y_i; f_ik, diag(s_i^2)).

  Exact as the draws grow, whatever the shape of the row's distribution. The default of a
  drop test, whose draws vary mainly in the measured inputs (stratified): a smeared impact
  parameter moves speed, angle and spin together along a bent curve, which a normal
  describes badly and the stratified draws resolve.
* ``"gaussian"``: a normal with the draws' mean ``m_i(theta)`` and covariance ``C_i(theta)``
  (including the Monte Carlo error of the mean, measured from the draws,
  :func:`draw_moments`),

      -2 ln L_i = r_i^T T_i^-1 r_i + ln det(2 pi T_i),  r_i = y_i - m_i,
      T_i = diag(s_i^2) + C_i.

  The default of a game, whose draws spread over several unmeasured inputs (the swing,
  the contact): there ``M`` draws resolve a mean and a covariance but not a density.

The draws are held fixed (common random numbers), so ``L`` is smooth in ``theta``. A coarse
grid and Nelder-Mead find the maximum. Intervals are profile-likelihood intervals (``-ln L``
rises by 1/2 when the other parameters are re-optimised; asymmetric in general); where the
likelihood stays flat up to the end of a parameter's range on one side, a one-sided 95 %
limit (a rise of 1.353) is reported instead, and a parameter flat on both sides is reported
as not identified. The curvature error (finite-difference Hessian) is kept as ``stderr``; a
parametric bootstrap is optional. The goodness of fit is the normal form's
``chi^2 = sum_i r_i^T T_i^-1 r_i`` at the best fit (for either likelihood), with
``dof = rows x observables - free parameters`` and its ``scipy.stats.chi2`` p-value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from mcbat.bodies.game import GAME_RESTITUTION
from mcbat.core.status import OK, STATUS_NAMES
from mcbat.errors import InputError
from mcbat.stats.measurements import DEFAULT_ERRORS, table_error
from mcbat.stats.models import (
    OUTLIER_SIGMA,
    PRIOR_RIDGE,
    UNITS_HINT,
    PriorFamily,
    draw_model,
    rows_text,
)

__all__ = ["FREE", "FitResult", "GRID_EVALUATIONS", "LIKELIHOODS", "Likelihood",
           "ModelComparison", "SEARCH", "compare_models", "fit"]

FREE = {"e": (1e-3, 1.0), "mu": (1e-3, 2.0), "ball_inertia_factor": (0.05, 1.0),
        "axial": (-1.0, 1.0), "e_x": (0.0, 1.0), "drag_scale": (0.2, 3.0),
        "lift_scale": (0.0, 3.0)}
"""Parameters that can be fitted, with their allowed ranges (``e_x``: the tangential
restitution of Cross & Nathan 2006, 0 = the rigid model; ``drag_scale``, ``lift_scale``:
the flight model's, :mod:`mcbat.stats.flight_model`)."""
PHYSICAL_EDGES = {("e", 1.0), ("e_x", 0.0), ("e_x", 1.0), ("mu", 1e-3), ("e", 1e-3),
                  ("lift_scale", 0.0)}
"""Ends of :data:`FREE` that are physical limits (an interval may end there); the other
ends (``mu = 2``, ...) only end the search, and a likelihood still flat there means the data
do not bound the parameter on that side."""
SEARCH = {"e": (0.05, 0.98), "mu": (0.01, 1.0), "ball_inertia_factor": (0.1, 0.8),
          "axial": (-0.05, 0.05), "e_x": (0.0, 0.6), "drag_scale": (0.5, 1.5),
          "lift_scale": (0.0, 2.0)}
"""Ranges of the coarse grid that starts the search (mu on a logarithmic grid: where
impacts slide, the likelihood changes fast with mu; where all stick it is flat)."""
GRID_EVALUATIONS = 121
"""Size of the coarse starting grid (11 x 11 for two parameters; at least 6 points a
parameter: 6^3 for three, ...)."""
STARTS = 2
"""Local searches from the best points of the grid (plus one from the profile scan in mu,
:data:`SCAN_POINTS`)."""
SCAN_POINTS = 48
"""Values of mu (log-spaced over its search range, 10 % apart) at which the profile is
scanned for the start of the local search."""
FINE_SIMPLEX = 20.0
"""A local search from a fine scan's point starts with a simplex this many times smaller
than one from the coarse grid."""
SHARE_BEYOND_WARNING = 0.05
"""A fit warns when the fitted prior of a measured input puts this share or more of the
true values beyond the study's range (or when the measured values reject that range)."""
ONE_SIGMA = 0.5
"""Rise of ``-ln L`` that ends a 68.3 % profile-likelihood interval."""
LIMIT_95 = 0.5 * stats.chi2.ppf(0.90, 1)
"""Rise of ``-ln L`` (1.353) that sets a one-sided 95 % limit."""
UNIT_SIGMA = 3.0
"""When half the rows of an observable or more lie this many sigma beyond every model
prediction over the search ranges, the column is refused with a hint about its unit (a
correct table has ~0.3 % of its rows that far from the true model)."""
MAGNITUDES = ("exit_speed", "launch_speed", "spin_rate")
"""Observables that are magnitudes: a wrong unit scales them, which the median shows."""
MEDIAN_FACTOR = 1.25
"""A magnitude column whose median lies beyond the model's medians over the search grid by
more than this factor is refused (m/s instead of mph: 2.24; km/h: 1.61; rpm/rad/s: 9.55)."""

MEDIAN_MAXIMUM = {"launch_speed": 125.0}
"""A magnitude column whose median lies above this (its unit) is in another unit whatever
the model gives: the fastest batted balls Statcast has measured are near 122 mph, so no
table of real balls has a median near 125 mph (km/h would put a typical 90 mph at 145)."""
P_VALUE_TOO_GOOD = 0.995
"""A chi-squared p-value above this is reported: the stated errors are larger than the
scatter of the data (or a column is in another unit)."""
PRESET_DEVIATION = 0.4
"""``e`` further than this fraction from the study's own value is reported (a baseball's
``e*`` is known to a few per cent; a fit far from it usually means a unit or a column is
wrong)."""
LIKELIHOODS = ("mixture", "gaussian")
"""The forms of a row's likelihood (module docstring)."""
_BAD = 1e30


@dataclass
class FitResult:
    """Best-fit parameters with uncertainties and the goodness of fit.

    ``stderr`` holds the curvature errors (``inf`` for a parameter the data do not bound,
    NaN where the curvature is not positive); ``intervals`` the profile-likelihood result
    per parameter: ``lower_error``, ``upper_error`` (positive, or None on a side the data do
    not bound), ``status`` (``"measured"``, ``"lower_limit"``, ``"upper_limit"`` or
    ``"unidentified"``, or ``"profile_failed"`` when the profile jumps at the best fit and
    no interval can be given: its ``stderr`` is then still the curvature error, which
    describes the likelihood only near the best fit), ``limit`` (the one-sided 95 % limit,
    or None) and ``at_bound`` (the physical edge the interval reaches, or None).
    """

    params: dict
    stderr: dict
    chi2: float
    dof: int
    p_value: float
    neg_log_likelihood: float
    bootstrap_stderr: dict = field(default_factory=dict)
    residuals: object = None
    unconstrained: list = field(default_factory=list)
    """Parameters the data do not bound on at least one side (status other than
    ``"measured"``): their ``stderr`` is inf and their value is not a measurement."""
    intervals: dict = field(default_factory=dict)
    priors: dict = field(default_factory=dict)
    """Measured input -> the flat prior its true values were marginalised over
    (:attr:`mcbat.stats.models._DrawModel.priors`: ``study_range``, ``range``, ``widened``,
    ``p_value``; table units)."""
    warnings: list = field(default_factory=list)
    """What a user should check before trusting the fit (a value at a bound or far from the
    study's, an implausibly good chi-squared, a widened prior), one sentence each."""

    @property
    def aic(self) -> float:
        """Akaike's information criterion, ``2 (-ln L) + 2 k``."""
        return 2.0 * self.neg_log_likelihood + 2.0 * len(self.params)

    def bic(self, n_points: int) -> float:
        """Bayesian information criterion, ``2 (-ln L) + k ln n`` for ``n_points`` values."""
        return 2.0 * self.neg_log_likelihood + len(self.params) * math.log(n_points)

    def to_dict(self) -> dict:
        """The fit as JSON-ready data (the ``mcbat fit --json`` output; non-finite numbers
        become None)."""
        params = {}
        for k, v in self.params.items():
            entry = {"value": v, "stderr": self.stderr.get(k, math.nan)}
            entry.update(self.intervals.get(k, {}))
            if k in self.bootstrap_stderr:
                entry["bootstrap_stderr"] = self.bootstrap_stderr[k]
            params[k] = entry
        return _finite({"params": params, "chi2": self.chi2, "dof": self.dof,
                        "p_value": self.p_value, "aic": self.aic,
                        "unconstrained": list(self.unconstrained),
                        "input_priors": self.priors, "warnings": list(self.warnings)})

    def lines(self) -> list[str]:
        """The parameters as printed by ``mcbat fit``, one string per line."""
        out = []
        for name, value in self.params.items():
            iv = self.intervals.get(name, {})
            status = iv.get("status", "measured")
            extra = (f"; bootstrap {self.bootstrap_stderr[name]:.2g}"
                     if name in self.bootstrap_stderr else "")
            curv = self.stderr.get(name, math.nan)
            curv = f"curvature +- {curv:.2g}" if math.isfinite(curv) else "no curvature error"
            if status == "measured":
                lo, hi = iv.get("lower_error"), iv.get("upper_error")
                edge = (f", reaching the physical bound {name} = {iv['at_bound']:g}"
                        if iv.get("at_bound") is not None else "")
                if lo is None:
                    out.append(f"  {name} = {value:.6g} +- {self.stderr[name]:.2g} "
                               f"(curvature{extra})")
                else:
                    out.append(f"  {name} = {value:.6g} -{lo:.2g} +{hi:.2g} (68 % profile "
                               f"likelihood{edge}; {curv}{extra})")
            elif status == "profile_failed":
                out.append(f"  {name} = {value:.6g}: the profile likelihood could not be "
                           f"computed (it jumps at the best fit), so no interval is given; "
                           f"{curv} describes the likelihood only near the best fit{extra}")
            elif status in ("lower_limit", "upper_limit"):
                sign, side = (">", "above") if status == "lower_limit" else ("<", "below")
                out.append(f"  {name} {sign} {iv['limit']:.4g} (95 % CL; the data do not "
                           f"bound {name} from {side}: best value {value:.4g} is not a "
                           f"measurement)")
            else:
                lo, hi = FREE[name]
                out.append(f"  {name}: not identified by the data (the likelihood is flat "
                           f"over {lo:g}..{hi:g}; {value:.4g} is not a measurement)")
        return out


def _finite(obj):
    """``obj`` with every non-finite float replaced by None (strict JSON)."""
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def check_free(free):
    """``free`` as a list of known, distinct parameter names, or :class:`InputError`."""
    if isinstance(free, str):
        free = [p.strip() for p in free.split(",")]
    free = list(free)
    if not free or any(not p for p in free):
        raise InputError("free", f"give one or more parameters, comma-separated, from "
                         f"{', '.join(FREE)}; got {','.join(free)!r}")
    unknown = [p for p in free if p not in FREE]
    if unknown:
        raise InputError("free", f"unknown parameter {unknown[0]!r} (choose from "
                         f"{', '.join(FREE)})")
    dup = sorted({p for p in free if free.count(p) > 1})
    if dup:
        raise InputError("free", f"parameter {dup[0]!r} given twice")
    return free


def _check_count(value, name, minimum):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(name, f"must be an integer >= {minimum}, got {value!r}")
    return int(value)


def check_bootstrap(n):
    """``n`` refits: 0 (none) or at least 2 (a spread needs two), or :class:`InputError`."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not (n == 0 or n >= 2):
        raise InputError("bootstrap", f"must be 0 (no bootstrap) or an integer >= 2, got {n!r}")
    return int(n)


class Likelihood:
    """``-ln L(theta)`` of a measurement table under a study's model (see module doc).

    Parameters
    ----------
    study : mcbat.study.Study or mcbat.study.game.GameStudy
        Fixed setup and nuisance scatter. A bat-frame study must place the contact by
        ``contact.impact_parameter`` (the ball's line offset from the bat axis).
    table : pandas.DataFrame
        Measurement table (:mod:`mcbat.stats.models` lists the columns of each kind of
        study, with their units): measured inputs, observables and ``_err`` columns
        (1 sigma, same units; an observable without one gets :func:`default_errors`).
    free : sequence of str
        Parameters to fit, from :data:`FREE` (the game model has ``e``, ``mu``, ``e_x``).
    draws : int, optional
        Draws per row (at least 4; default 48 for a drop test, 128 for a game:
        :attr:`mcbat.stats.models.GameModel.DEFAULT_DRAWS` says why).
    seed : int
        Seed of the draws.
    fixed : dict, optional
        Parameters held at given values (``{"e_x": 0.0}``: the rigid model).
    input_prior : {"cover", "widen", "study"}, optional
        The range the true values of an input with an ``_err`` column are marginalised
        over (:mod:`mcbat.stats.models`): ``"cover"`` the study's range widened to cover
        the data, with a fitted step in the prior at the study's ends (the mixture
        likelihood's default); ``"widen"`` the study's range, widened only when the
        measured values reject it (the normal likelihood's default); ``"study"`` the
        study's range, refusing a table whose measured values reject it.
    likelihood : {"mixture", "gaussian"}, optional
        The form of each row's likelihood (module docstring); default: the model's
        (``"mixture"`` for a drop test, ``"gaussian"`` for a game).
    """

    def __init__(self, study, table, free, draws=None, seed=0, fixed=None,
                 input_prior=None, likelihood=None):
        if likelihood is not None and likelihood not in LIKELIHOODS:
            raise InputError("likelihood", f"must be one of {', '.join(LIKELIHOODS)}, got "
                             f"{likelihood!r}")
        self.free = check_free(free)
        draws = None if draws is None else _check_count(draws, "draws", 4)
        seed = _check_count(seed, "seed", 0)
        self.model = draw_model(study, table, draws, seed, fixed, input_prior, likelihood)
        for name in self.free:
            if name not in self.model.PARAMETERS:
                raise InputError("free", f"{name!r} is not a parameter of a "
                                 f"{self.model.KIND} study (choose from "
                                 f"{', '.join(self.model.PARAMETERS)})")
        self.source = self.model.source
        self.study = study
        self.rows, self.draws = self.model.rows, self.model.draws
        self.observables = self.model.observables
        self.units = {c: self.model.COLUMNS[c][0] for c in self.observables}
        self.search = {**SEARCH, **self.model.SEARCH}
        """The coarse grid's ranges for this study's model (:data:`SEARCH`, narrowed by
        the model's own)."""
        self.y = np.stack([table[c].to_numpy(float) for c in self.observables], axis=1)
        self.s2 = np.stack([table[f"{c}_err"].to_numpy(float) ** 2 if f"{c}_err" in table
                            else default_errors(c, self.y[:, j]) ** 2
                            for j, c in enumerate(self.observables)], axis=1)
        self.likelihood = likelihood or self.model.LIKELIHOOD
        self.calls = 0
        self.failure = None
        self.envelope = None
        self._draws = None
        # The mixture likelihood estimates the prior of each measured input over a bounded
        # range with the parameters, by reweighting its draws (module docstring).
        self.prior_families = {}
        blocks = []
        if self.likelihood == "mixture":
            for name, (values, lo, hi) in self.model.prior_draws.items():
                inner = (self.model.priors[name]["study_range"]
                         if self.model.input_prior == "cover" else None)
                family = PriorFamily(lo, hi, inner=inner)
                self.prior_families[name] = family
                blocks.append(family.basis_at(values))
        self._prior_basis = np.concatenate(blocks, axis=2) if blocks else None
        self.prior_coefficients = np.zeros(0 if not blocks else self._prior_basis.shape[2])
        """The prior's coefficients at the last evaluation (one block of
        :data:`mcbat.stats.models.PRIOR_DEGREE` per measured input in
        :attr:`prior_families`)."""

    def predict(self, theta):
        """Model mean and covariance per row at ``theta``, or None (and the reason in
        :attr:`failure`) when some row has fewer than two good draws.

        Returns
        -------
        mean : ndarray, (rows, observables)
            Mean over the good draws (units of the observables).
        cov : ndarray, (rows, observables, observables)
            The draws' covariance plus the Monte Carlo error of their mean
            (:func:`draw_moments`).
        n_ok : ndarray, (rows,)
            Number of good draws.
        """
        self.model.set_parameters(dict(zip(self.free, map(float, theta))))
        values, status = self.model.solve()
        self.calls += 1
        ok = (status == OK).reshape(self.rows, self.draws)
        n_ok = ok.sum(axis=1)
        if (n_ok < 2).any():
            bad = n_ok < 2
            codes = status.reshape(self.rows, self.draws)[bad]
            worst = np.bincount(codes[codes != OK], minlength=len(STATUS_NAMES))
            name = STATUS_NAMES[int(np.argmax(worst))]
            self.failure = (bad, name, dict(zip(self.free, map(float, theta))))
            return None
        sims = np.stack([values[c].reshape(self.rows, self.draws) for c in self.observables],
                        axis=2)
        plain = self.model.plain_draws  # the draws given the measured inputs alone
        mean, cov = draw_moments(sims[:, :plain], ok[:, :plain])
        self._draws = (sims, ok)
        return mean, cov, n_ok

    def _evaluate(self, theta):
        """``(-ln L, Mahalanobis distance squared per row, total covariance, mean)`` or
        None."""
        pred = self.predict(theta)
        if pred is None:
            return None
        mean, cov, _ = pred
        total = cov + self.s2[:, :, None] * np.eye(len(self.observables))
        sign, logdet = np.linalg.slogdet(total)
        if not (sign > 0).all():
            return None
        resid = self.y - mean
        quad = np.einsum("ri,ri->r", resid, np.linalg.solve(total, resid[:, :, None])[..., 0])
        if self.likelihood == "mixture":
            nll = self._mixture_nll(*self._draws)
        else:
            nll = 0.5 * (quad.sum() + logdet.sum() + resid.size * math.log(2 * math.pi))
        return float(nll), quad, total, mean

    def _mixture_nll(self, sims, ok):
        """``-sum_i ln((1 / n_i) sum_k N(y_i; sims_ik, diag(s2_i)) g(b_ik))`` over the good
        draws, minimised over the priors' coefficients (``g = 1`` without a prior to fit).

        The draws of a measured input come from its posterior under a flat prior, so
        weighting draw ``k`` by ``g(b_ik)``, the prior's density, makes the average the
        likelihood under prior ``g``, including what the measured inputs say about ``g``.
        Minimising over the coefficients profiles the prior out of the parameters'
        likelihood, so its uncertainty is in their intervals."""
        log_density = -0.5 * ((self.y[:, None, :] - sims) ** 2 / self.s2[:, None, :]).sum(axis=2)
        if self.model.draw_log_weight is not None:
            log_density = log_density + self.model.draw_log_weight
        log_density = np.where(ok, log_density, -np.inf)
        const = 0.5 * float(np.log(2 * math.pi * self.s2).sum()) + float(
            np.log(ok.sum(axis=1)).sum())
        if self._prior_basis is None:
            top = log_density.max(axis=1)
            return float(-(top + np.log(np.exp(log_density - top[:, None]).sum(axis=1))).sum()
                         + const)
        basis, families, rows = self._prior_basis, list(self.prior_families.values()), self.rows
        size = basis.shape[2]

        def cost(alpha, hessian=False):
            """F(alpha), its gradient and (optionally) its Hessian."""
            total = log_density + basis @ alpha
            top = total.max(axis=1)
            weights = np.exp(total - top[:, None])
            sums = weights.sum(axis=1)
            share = weights / sums[:, None]
            mean_basis = np.einsum("rk,rkj->rj", share, basis)
            value = -float((top + np.log(sums)).sum()) + 0.5 * PRIOR_RIDGE * float(alpha @ alpha)
            grad = -mean_basis.sum(axis=0) + PRIOR_RIDGE * alpha
            hess = None
            if hessian:  # -sum_i Cov_i(B) + rows Cov_g(P) + ridge
                hess = -(np.einsum("rk,rkj,rkl->jl", share, basis, basis)
                         - mean_basis.T @ mean_basis) + PRIOR_RIDGE * np.eye(size)
            at = 0
            for family in families:
                block = slice(at, at + family.size)
                log_norm, mean_p, cov_p = family.log_norm(alpha[block], second=True)
                value += rows * log_norm
                grad[block] += rows * mean_p
                if hessian:
                    hess[block, block] += rows * cov_p
                at += family.size
            return value, grad, hess

        def newton(alpha):
            """Damped Newton steps from ``alpha``; the damping keeps each step a descent
            where the Hessian is not positive."""
            value, grad, hess = cost(alpha, True)
            damping = 1e-6
            for _ in range(100):
                if np.max(np.abs(grad)) < 1e-8:
                    break
                while damping <= 1e12:
                    try:
                        step = -np.linalg.solve(hess + damping * np.eye(size), grad)
                    except np.linalg.LinAlgError:  # singular: more damping makes it regular
                        step = None
                    if step is not None and grad @ step < 0 and cost(alpha + step)[0] <= value:
                        break
                    damping *= 10.0
                if damping > 1e12:
                    break
                alpha = alpha + step
                value, grad, hess = cost(alpha, True)
                damping = max(damping / 10.0, 1e-6)
            return value, alpha

        # From the last coefficients (a few steps when theta moved a little) and from the
        # flat prior: the cost need not be convex, and a start left far away by a distant
        # theta (a corner of the search grid) can end in another minimum.
        value, alpha = min(newton(self.prior_coefficients.copy()), newton(np.zeros(size)),
                           key=lambda found: found[0])
        self.prior_coefficients = alpha
        return float(value) + const

    def refine(self, theta):
        """With the mixture likelihood, place half of each row's draws of a smeared measured
        input near its posterior given the observables at ``theta`` (a point near the best
        fit: :meth:`mcbat.stats.models.BatFrameModel.refine_draws`), and rebuild the
        prior's basis at the new draws. Call before the local search: the draws stay fixed
        from then on."""
        refine = getattr(self.model, "refine_draws", None)
        if self.likelihood != "mixture" or refine is None:
            return
        self.model.set_parameters(dict(zip(self.free, map(float, theta))))
        if not refine(self.y, self.s2, self.observables):
            return
        if self.prior_families:
            self._prior_basis = np.concatenate(
                [family.basis_at(self.model.prior_draws[name][0])
                 for name, family in self.prior_families.items()], axis=2)
            self.prior_coefficients = np.zeros(self._prior_basis.shape[2])
        self._draws = None

    def __call__(self, theta):
        """``-ln L`` at the free parameters ``theta`` (1e30 outside their ranges or where
        the likelihood cannot be evaluated)."""
        for name, value in zip(self.free, theta):
            lo, hi = FREE[name]
            if not lo <= value <= hi:
                return _BAD
        got = self._evaluate(theta)
        if got is None:
            return _BAD
        nll, _, total, mean = got
        if self.envelope is not None:  # the range of predictions over the search grid
            lo, hi, sd, med_lo, med_hi = self.envelope
            np.minimum(lo, mean, out=lo)
            np.maximum(hi, mean, out=hi)
            np.maximum(sd, np.sqrt(np.diagonal(total, axis1=1, axis2=2)), out=sd)
            med = np.median(mean, axis=0)
            np.minimum(med_lo, med, out=med_lo)
            np.maximum(med_hi, med, out=med_hi)
        return nll if math.isfinite(nll) else _BAD

    def chi2(self, theta):
        """``sum_i r_i^T T_i^-1 r_i`` at ``theta`` (``r_i`` the residuals of row ``i``, ``T_i``
        its total covariance): chi-squared with ``rows x observables`` terms."""
        got = self._evaluate(theta)
        if got is None:
            raise self.failure_error()
        return float(got[1].sum())

    def residuals(self, theta):
        """Normalised residuals ``(measured - model mean) / sigma`` at ``theta``, one row per
        measurement and one column per observable (``sigma``: the square root of the
        diagonal of the total covariance)."""
        got = self._evaluate(theta)
        if got is None:
            raise self.failure_error()
        _, _, total, mean = got
        return (self.y - mean) / np.sqrt(np.diagonal(total, axis1=1, axis2=2))

    def simulate(self, theta, rng):
        """A table of observables drawn from the model at ``theta`` (the bootstrap's)."""
        _, _, total, mean = self._evaluate(theta)
        z = rng.standard_normal(mean.shape)
        return mean + np.einsum("rij,rj->ri", np.linalg.cholesky(total), z)

    def failure_error(self):
        """An :class:`InputError` saying which rows could not be evaluated, and why."""
        bad, status, theta = self.failure
        where = ", ".join(f"{k} = {v:.4g}" for k, v in theta.items())
        hints = {"max_steps": (None, " (the solver's step budget: raise [solver] max_steps)"),
                 **self.model.FAILURE_HINTS}
        column, hint = hints.get(status, (None, ""))
        return InputError(column, f"the likelihood cannot be evaluated: {rows_text(bad)} "
                          f"({int(bad.sum())} of {self.rows}) have no good impact among their "
                          f"{self.draws} draws (status {status}{hint}) at {where}",
                          self.source)

    def check_envelope(self):
        """Refuse rows far outside anything the model predicted over the search grid."""
        lo, hi, sd, med_lo, med_hi = self.envelope
        for j, col in enumerate(self.observables):
            y = self.y[:, j]
            if col in MAGNITUDES:
                # A column in another unit is a scaled copy of the right one: its median
                # lies outside the span of the model's medians over the whole search grid
                # by more than the model can stretch. The rows' own spread (nuisance
                # scatter of a game, ~10 mph) hides that from the row-by-row test below
                # when the table is small or the unit is close (m/s against mph).
                median = float(np.median(y))
                low, high = med_lo[j] / MEDIAN_FACTOR, med_hi[j] * MEDIAN_FACTOR
                if median > MEDIAN_MAXIMUM.get(col, math.inf):
                    raise InputError(col, f"the measured median {median:.3g} "
                                     f"{self.units[col]} is faster than any batted ball "
                                     f"measured (about 122 mph): {UNITS_HINT[col]}",
                                     self.source)
                if not low <= median <= high:
                    raise InputError(col, f"the measured median {median:.3g} "
                                     f"{self.units[col]} lies outside anything the model "
                                     f"gives for this study over the search grid (medians "
                                     f"{med_lo[j]:.3g}..{med_hi[j]:.3g} {self.units[col]}): "
                                     f"{UNITS_HINT[col]}", self.source)
            beyond = np.maximum(lo[:, j] - y, y - hi[:, j]) / sd[:, j]
            far = beyond > OUTLIER_SIGMA
            many = beyond > UNIT_SIGMA
            span = f"{np.min(lo[:, j]):.3g}..{np.max(hi[:, j]):.3g} {self.units[col]}"
            if many.sum() >= 0.5 * self.rows:
                raise InputError(col, f"{int(many.sum())} of {self.rows} rows lie far outside "
                                 f"anything the model gives for this study (model "
                                 f"{span}, measured median {np.median(y):.3g}): "
                                 f"{UNITS_HINT[col]}", self.source)
            if not far.any():
                continue
            raise InputError(col, f"{rows_text(far, y)}: more than {OUTLIER_SIGMA:g} sigma "
                             f"beyond anything the model gives for this study (model {span}): "
                             f"a typo or another unit? Fix or remove the row", self.source)


def draw_moments(sims, ok):
    """Mean and covariance of the predicted observables of each row, from its draws.

    Parameters
    ----------
    sims : ndarray, (rows, draws, observables)
        The draws' observables (anything where ``ok`` is False).
    ok : ndarray of bool, (rows, draws)
        Draws whose impact was solved.

    Returns
    -------
    mean : ndarray, (rows, observables)
    cov : ndarray, (rows, observables, observables)
        ``C + 2 V``: ``C`` the draws' covariance about their mean (divided by the number
        ``n`` of good draws) and ``V`` the Monte Carlo covariance of that mean, measured by
        pairing neighbouring draws ``(0, 1), (2, 3), ...`` (the collapsed-strata estimate
        ``sum (d d^T) / (2 n P)`` over the ``P`` pairs of good draws, ``d`` the pair's
        difference). Draws of a row are stratified in a smeared measured input
        (:mod:`mcbat.stats.models`), so neighbours lie in neighbouring slices and ``V`` is
        small where that input dominates; with independent draws ``E[V] = Sigma / n`` and
        ``E[C + 2 V] = Sigma (1 + 1/n)``, the textbook variance of ``y - mean``. In general
        ``E[C] = Sigma - V``: ``C + V`` estimates the spread and the second ``V`` the error
        of the mean, so neither counts twice.
    """
    rows, draws, _ = sims.shape
    w = ok.astype(float)
    n = w.sum(axis=1)
    x = np.where(ok[:, :, None], sims, 0.0)
    mean = x.sum(axis=1) / n[:, None]
    dev = (x - mean[:, None, :]) * w[:, :, None]
    cov = np.einsum("rkd,rke->rde", dev, dev) / n[:, None, None]
    even = draws - draws % 2
    both = w[:, 0:even:2] * w[:, 1:even:2]
    diff = (x[:, 0:even:2] - x[:, 1:even:2]) * both[:, :, None]
    pairs = both.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        paired = np.einsum("rkd,rke->rde", diff, diff) / (2.0 * pairs * n)[:, None, None]
        independent = cov / (n - 1.0)[:, None, None]  # a row without a pair of good draws
    error_of_mean = np.where((pairs > 0)[:, None, None], paired, independent)
    return mean, cov + 2.0 * error_of_mean


def default_errors(column, values):
    """1-sigma errors of an observable without an ``_err`` column, one per row of
    ``values`` (the column's measured values), all equal: ``max(relative x mean |y|,
    floor)`` with :data:`DEFAULT_ERRORS` (:func:`mcbat.stats.measurements.table_error`; the
    mean over the finite values). Not ``relative |y|`` row by row: a row's error would then
    grow with its measured value and tell the fit which rows lie above the model's mean,
    biasing the estimates (docs/fitting.md)."""
    relative, floor = DEFAULT_ERRORS[column]
    values = np.asarray(values, dtype=float)
    return np.full(values.shape, table_error(values, relative, floor))


def fit(study, table, free=("e", "mu"), *, draws=None, seed=0, bootstrap=0, start=None,
        fixed=None, intervals="profile", input_prior=None, likelihood=None):
    """Maximum-likelihood fit of ``free`` parameters to ``table`` (see the module doc).

    Parameters
    ----------
    study : mcbat.study.Study
        Fixed setup and nuisance scatter.
    table : pandas.DataFrame
        A measurement table (:func:`mcbat.stats.measurements.read_measurements`).
    free : sequence of str
        Parameters to fit, from :data:`FREE` (distinct).
    draws : int, optional
        Draws per row (nuisance scatter and measured-input errors; default: the model's,
        48 for a drop test, 128 for a game).
    seed : int
        Seed of the draws (and of the bootstrap).
    bootstrap : int
        Number of parametric bootstrap refits (0: none, else at least 2).
    start : sequence of float, optional
        Starting point; default: the best point of a coarse grid over :data:`SEARCH`.
    fixed : dict, optional
        Inputs held at given values instead of the study's (``{"e_x": 0.0}``: rigid).
    intervals : {"profile", "curvature"}
        ``"profile"``: profile-likelihood intervals and limits (:attr:`FitResult.intervals`);
        ``"curvature"``: the Hessian errors only (faster).
    input_prior : {"cover", "widen", "study"}, optional
        See :class:`Likelihood`; the prior used is in :attr:`FitResult.priors`.
    likelihood : {"mixture", "gaussian"}, optional
        See :class:`Likelihood` (default: the model's).

    Raises
    ------
    InputError
        Naming the parameter, the option or the table column: unknown or repeated
        parameters, rows the model cannot evaluate, values far outside anything the model
        produces (a wrong unit), ...
    """
    bootstrap = check_bootstrap(bootstrap)
    if intervals not in ("profile", "curvature"):
        raise InputError("intervals", f"must be 'profile' or 'curvature', got {intervals!r}")
    like = Likelihood(study, table, free, draws=draws, seed=seed, fixed=fixed,
                      input_prior=input_prior, likelihood=likelihood)
    if start is None:
        # The likelihood has flat regions (e.g. every impact sticks above some mu, and then
        # mu does not matter): a coarse grid over the search ranges finds the right basin
        # before the local search. The grid also gives the range of the model's predictions,
        # against which values in a wrong unit are refused.
        points = max(6, round(GRID_EVALUATIONS ** (1.0 / len(like.free))))
        axes = [np.geomspace(*like.search[p], points) if p == "mu"
                else np.linspace(*like.search[p], points) for p in like.free]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
        shape = like.y.shape
        n_obs = shape[1]
        like.envelope = (np.full(shape, np.inf), np.full(shape, -np.inf), np.zeros(shape),
                         np.full(n_obs, np.inf), np.full(n_obs, -np.inf))
        values = np.array([like(x) for x in grid])
        if not (values < _BAD).any():
            raise like.failure_error()
        like.check_envelope()
        like.envelope = None
        starts = list(grid[np.argsort(values)[:STARTS]])
        like.refine(starts[0])
        fine = []
        if "mu" in like.free:
            # The valley below the plateau can be narrower than the grid's spacing in mu
            # and out of a local search's reach from the grid (it may drift up the
            # plateau's gentle slope instead): a fine line in mu through the grid's best
            # point is cheap and finds it.
            i = like.free.index("mu")
            line = np.repeat(starts[0][None, :], SCAN_POINTS, axis=0)
            line[:, i] = np.geomspace(*like.search["mu"], SCAN_POINTS)
            fine.append(line[int(np.argmin([like(x) for x in line]))])
        if "mu" in like.free and _flat(like, starts[0], "mu"):
            # Where every impact sticks the likelihood is flat in mu, and the best value can
            # lie in a valley narrower than the coarse grid's spacing just below that
            # plateau (60 drops with 5 mm input errors: a valley 1.3x wide in mu, 29 units
            # of -ln L below the plateau, between two grid points). A local search that
            # starts on the plateau drifts along it to the end of the range; a fine scan of
            # the profile in mu finds the valley.
            fine.append(_profile_scan(like, starts[0], "mu"))
    else:
        starts, fine = [np.asarray(start, float)], []
        like.refine(starts[0])
        if not like(starts[0]) < _BAD:
            raise like.failure_error() if like.failure else InputError(
                "start", f"outside the parameter ranges: {list(starts[0])}")
    scale = np.array([0.05 * (like.search[p][1] - like.search[p][0]) for p in like.free])
    # Local searches from the best grid points: the likelihood can have a second basin
    # (e.g. every drop stuck at large mu, with e_x = 0) that one start would settle in.
    # A start from a fine scan sits in a valley that may be narrower than the coarse
    # simplex (a few percent wide in mu): its search starts with a simplex of a twentieth
    # of the size, which stays in the valley instead of stepping over it onto the plateau.
    res = min([_minimize(like, x0, scale) for x0 in starts]
              + [_minimize(like, x0, scale / FINE_SIMPLEX) for x0 in fine],
              key=lambda r: r.fun)
    if "mu" in like.free and start is None and _flat(like, res.x, "mu"):
        # Ended on the plateau: the grid's best point can sit at an e far enough from the
        # best one that the line in mu misses the valley; a scan of the profile from the
        # end point re-optimises e at every mu.
        scanned = _minimize(like, _profile_scan(like, res.x, "mu"), scale / FINE_SIMPLEX)
        res = min(res, scanned, key=lambda r: r.fun)
    best, nll_min = res.x, float(res.fun)
    err, cov = _curvature_errors(like, best)
    summary = {}
    if intervals == "profile":
        summary, better = _profile(like, best, nll_min, err, cov)
        if better is not None:  # the profile found a lower point: restart from it
            res = _minimize(like, better, scale)
            best, nll_min = res.x, float(res.fun)
            err, cov = _curvature_errors(like, best)
            summary, _ = _profile(like, best, nll_min, err, cov)
        unconstrained = [p for p in like.free
                         if summary[p]["status"] not in ("measured", "profile_failed")]
    else:
        unconstrained = _flat_to_edge(like, best, nll_min)
    for name in unconstrained:
        err[like.free.index(name)] = math.inf
    r = like.residuals(best)
    chi2 = like.chi2(best)
    priors = {name: dict(prior) for name, prior in like.model.priors.items()}
    at = 0
    for name, family in like.prior_families.items():  # coefficients at the best point
        if family.step:
            priors[name]["share_beyond_study_range"] = family.share_outside(
                like.prior_coefficients[at:at + family.size])
        at += family.size
    dof = int(r.size - len(best))
    result = FitResult(params=dict(zip(like.free, map(float, best))),
                       stderr=dict(zip(like.free, map(float, err))), chi2=chi2, dof=dof,
                       p_value=float(stats.chi2.sf(chi2, dof)) if dof > 0 else math.nan,
                       neg_log_likelihood=nll_min, residuals=r,
                       unconstrained=unconstrained, intervals=summary, priors=priors)
    result.warnings = _warnings(like, result)
    if bootstrap:
        result.bootstrap_stderr = _bootstrap(like, best, bootstrap, seed)
    return result


def _flat(like, x, name):
    """True when ``-ln L`` changes by less than 1e-4 (a five-thousandth of the rise that
    ends a 68 % interval, and above the precision of a likelihood that optimises a prior
    inside) with a 10 % larger ``name`` at ``x``."""
    i = like.free.index(name)
    probe = np.array(x, float)
    probe[i] = min(probe[i] * 1.1, FREE[name][1])
    return abs(like(probe) - like(x)) < 1e-4


def _profile_scan(like, x0, name, points=SCAN_POINTS):
    """The lowest point of the profile of ``name`` over its search range (log-spaced for
    ``mu``), the other free parameters re-optimised at each value, each search starting
    from the previous value's optimum (loosely: the point only starts the local search)."""
    i = like.free.index(name)
    lo, hi = like.search[name]
    values = np.geomspace(lo, hi, points) if name == "mu" else np.linspace(lo, hi, points)
    others = [j for j in range(len(x0)) if j != i]
    x = np.array(x0, float)
    best_x, best_nll = x.copy(), like(x)
    for t in values:
        x[i] = t
        if len(others) == 1:
            j = others[0]

            def sub1(y, j=j):
                x[j] = y
                return like(x)
            step = 0.05 * (like.search[like.free[j]][1] - like.search[like.free[j]][0])
            lo_j, hi_j = FREE[like.free[j]]
            y0 = min(max(x[j], lo_j + step), hi_j - step)
            r = optimize.minimize_scalar(sub1, bracket=(y0 - step, y0 + step), method="brent",
                                         options={"xtol": 1e-3, "maxiter": 40})
            x[j] = r.x
            nll = float(r.fun)
        elif others:
            def sub(y):
                x[others] = y
                return like(x)
            y0 = x[others].copy()
            step = [0.05 * (like.search[like.free[j]][1] - like.search[like.free[j]][0])
                    for j in others]
            simplex = np.vstack([y0] + [y0 + np.eye(len(others))[k] * step[k] *
                                        (1 if y0[k] + step[k] <= FREE[like.free[j]][1] else -1)
                                        for k, j in enumerate(others)])
            r = optimize.minimize(sub, y0, method="Nelder-Mead",
                                  options={"xatol": 1e-3 * min(step), "fatol": 0.05,
                                           "maxiter": 60 * len(others),
                                           "initial_simplex": simplex})
            x[others] = r.x
            nll = float(r.fun)
        else:
            nll = like(x)
        if nll < best_nll:
            best_x, best_nll = x.copy(), nll
    return best_x


def _warnings(like, result):
    """The sentences of :attr:`FitResult.warnings`."""
    out = []
    for name, prior in result.priors.items():
        share = prior.get("share_beyond_study_range")
        if prior.get("rejects_study_range") or (share or 0.0) >= SHARE_BEYOND_WARNING:
            (slo, shi), (lo, hi) = prior["study_range"], prior["range"]
            fitted = ("" if share is None else f", and the fitted prior puts "
                      f"{100 * share:.2g} % of them beyond the study's range")
            out.append(f"{name}: the measured values reach beyond the study's range "
                       f"{slo:.4g}..{shi:.4g} (p = {prior['p_value']:.2g} if every true "
                       f"value lay within it); their true values were marginalised over the "
                       f"widened range {lo:.4g}..{hi:.4g}{fitted}")
    for name, value in result.params.items():
        lo, hi = FREE[name]
        status = result.intervals.get(name, {}).get("status", "measured")
        if status == "measured" and ((value - lo < 1e-6 and (name, lo) not in PHYSICAL_EDGES)
                                     or (hi - value < 1e-6 and (name, hi) not in PHYSICAL_EDGES)):
            out.append(f"{name} = {value:.4g} sits at the end of its allowed range "
                       f"{lo:g}..{hi:g}: the data push beyond what the model allows")
        if name != "e":
            continue
        search_lo, search_hi = like.search[name]
        preset = getattr(like.model, "study_values", {}).get(name)
        outside = not search_lo <= value <= search_hi
        far = preset is not None and abs(value - preset) > PRESET_DEVIATION * preset
        if outside or far:
            where = [f"far from the study's value {preset:.4g}"] if far else []
            if outside:
                where.append(f"outside the range the fit searched ({search_lo:g}.."
                             f"{search_hi:g})")
            out.append(f"e = {value:.4g} is {' and '.join(where)}: check the units of the "
                       f"observables (docs/fitting.md)")
    if math.isfinite(result.p_value) and result.p_value > P_VALUE_TOO_GOOD:
        out.append(f"the fit is implausibly good (p-value {result.p_value:.4f}): the stated "
                   f"errors are larger than the scatter of the data, or a column is in "
                   f"another unit")
    return out


def _minimize(like, x0, scale):
    """Nelder-Mead from ``x0`` with a simplex of ``scale`` (tolerances well below any error)."""
    simplex = np.vstack([x0] + [x0 + np.eye(len(x0))[i] * scale[i] *
                                (1 if x0[i] + scale[i] <= FREE[p][1] else -1)
                                for i, p in enumerate(like.free)])
    return optimize.minimize(like, x0, method="Nelder-Mead",
                             options={"xatol": 1e-5, "fatol": 1e-5, "maxiter": 4000,
                                      "initial_simplex": simplex})


def _curvature_errors(like, best):
    """Curvature errors and covariance (NaN where the Hessian is not positive definite)."""
    hess = _hessian(like, best, [FREE[p] for p in like.free])
    n = len(best)
    try:
        np.linalg.cholesky(hess)
        cov = np.linalg.inv(hess)
        return np.sqrt(np.diag(cov)), cov
    except np.linalg.LinAlgError:
        diag = np.diag(hess)
        err = np.where(diag > 0, 1.0 / np.sqrt(np.abs(diag)), np.nan)
        return err, np.full((n, n), np.nan)


def _flat_to_edge(like, best, nll_min):
    """Parameters whose likelihood stays within 2 of the minimum up to a search edge."""
    flat = []
    for i, name in enumerate(like.free):
        for edge in like.search[name]:
            if edge in FREE[name]:
                continue  # a physical bound (e_x = 0), not the end of the search
            probe = best.copy()
            probe[i] = edge
            if abs(edge - best[i]) > 1e-9 and like(probe) - nll_min < 2.0:
                flat.append(name)
                break
    return flat


def _profile(like, best, nll_min, err, cov):
    """Profile-likelihood intervals of every free parameter.

    Returns the per-parameter summary (:attr:`FitResult.intervals`) and a better point if
    the profile found one (``-ln L`` lower than at ``best`` by more than 1e-3), else None.
    """
    n = len(best)
    # Steps of the profile: the curvature error, but never more than a twentieth of the
    # search range (in a flat region the curvature error is huge, and an inner search that
    # starts that far away lands anywhere, which made the profile jump at the best fit).
    widths = np.array([0.05 * (like.search[p][1] - like.search[p][0]) for p in like.free])
    finite = np.isfinite(err) & (err > 0)
    scale = np.where(finite, np.minimum(np.where(finite, err, 0.0), widths), widths)
    # The covariance's line is a good start for the other parameters only where the
    # curvature describes the likelihood: every error finite and within its step.
    on_line = bool(np.all(np.isfinite(cov)) and np.all(finite) and np.all(err <= widths))
    found = {"x": None, "nll": nll_min - 1e-3}

    def profile(i, t):
        """Min over the other parameters of -ln L with parameter i at t; the point."""
        others = [j for j in range(n) if j != i]
        x = best.copy()
        x[i] = t
        if others and on_line:  # start on the line of the covariance
            x[others] += cov[others, i] / cov[i, i] * (t - best[i])
            for j in others:
                lo, hi = FREE[like.free[j]]
                x[j] = min(max(x[j], lo), hi)
        if not others:
            value = like(x)
        elif len(others) == 1:  # Brent's method along the one other parameter
            j = others[0]

            def sub1(y):
                x[j] = y
                return like(x)
            y0, s = x[j], scale[j]
            lo, hi = FREE[like.free[j]]
            y0 = min(max(y0, lo + s), hi - s) if hi - lo > 2 * s else y0
            r = optimize.minimize_scalar(sub1, bracket=(y0 - s, y0 + s), method="brent",
                                         options={"xtol": 0.01 * s / max(abs(y0), s),
                                                  "maxiter": 60})
            x[j] = r.x
            value = float(r.fun)
        else:
            def sub(y):
                x[others] = y
                return like(x)
            y0 = x[others].copy()
            simplex = np.vstack([y0] + [y0 + np.eye(len(others))[k] * scale[j] *
                                        (1 if y0[k] + scale[j] <= FREE[like.free[j]][1]
                                         else -1)
                                        for k, j in enumerate(others)])
            r = optimize.minimize(sub, y0, method="Nelder-Mead",
                                  options={"xatol": 0.01 * scale[others].min(), "fatol": 1e-4,
                                           "maxiter": 400, "initial_simplex": simplex})
            x[others] = r.x
            value = float(r.fun)
        if value < found["nll"]:
            found["x"], found["nll"] = x.copy(), value
        return value - nll_min

    summary = {}
    for i, name in enumerate(like.free):
        lo_edge, hi_edge = FREE[name]
        sides = {}
        for sign, edge in ((-1, lo_edge), (1, hi_edge)):
            sides[sign] = _side(lambda t, i=i: profile(i, t), best[i], sign, edge,
                                scale[i], (name, edge) in PHYSICAL_EDGES)
        summary[name] = _entry(sides[-1], sides[1], lambda sign, side, i=i: _limit(
            lambda t: profile(i, t), best[i], sign, side["edge"], scale[i], side["root"]))
    return summary, found["x"]


def _entry(lower, upper, limit):
    """The :attr:`FitResult.intervals` entry of one parameter from its two sides;
    ``limit(sign, side)`` computes a one-sided 95 % limit."""
    entry = {"lower_error": lower["error"], "upper_error": upper["error"],
             "status": "measured", "limit": None, "at_bound": None}
    if lower.get("failed") or upper.get("failed"):
        entry.update(lower_error=None, upper_error=None, status="profile_failed")
        return entry
    for side in (lower, upper):
        if side["physical"]:
            entry["at_bound"] = side["edge"]
    if lower["error"] is None and upper["error"] is None:
        entry["status"] = "unidentified"
    elif upper["error"] is None or lower["error"] is None:
        sign, side = (-1, lower) if upper["error"] is None else (1, upper)
        entry["status"] = "lower_limit" if sign < 0 else "upper_limit"
        # The bounded side's 95 % limit, or the physical edge its interval reaches.
        entry["limit"] = limit(sign, side) if side["root"] is not None else side["edge"]
    return entry


def _side(delta, best, sign, edge, scale, physical):
    """One side of a profile interval: where ``delta`` (the rise of ``-ln L``) reaches 1/2.

    ``error`` is the distance from ``best`` (None if the rise stays below 1/2 up to a
    non-physical ``edge``; the distance to the edge if it is a physical limit);
    ``root`` is where the rise is 1/2.
    """
    result = {"error": None, "physical": False, "edge": edge, "root": None}
    room = abs(edge - best)
    if room < 1e-12:
        if physical:
            result.update(error=0.0, physical=True)
        return result
    steps = [1.3, 2.0, 3.0, 5.0, 8.0, 13.0, 21.0, 40.0, 80.0]
    last_t, last_d = best, 0.0
    points = []
    for k in steps:
        t = best + sign * min(k * scale, room)
        d = delta(t)
        points.append((t, d))
        if d >= ONE_SIGMA:
            break
        last_t, last_d = t, d
        if abs(t - best) >= room:
            break
    t, d = points[-1]
    if d < ONE_SIGMA:  # flat up to the edge (or beyond the scan)
        if abs(t - best) >= room and physical:
            result.update(error=room, physical=True)
        return result
    root = _crossing(delta, ONE_SIGMA, (last_t, last_d), (t, d), 0.005 * scale)
    if abs(root - best) < 1e-3 * scale:
        # A rise of 1/2 within a thousandth of the step is a jump of the profile, not an
        # interval: the profile could not be computed there (FitResult: "profile_failed").
        result["failed"] = True
        return result
    result["error"] = abs(root - best)
    result["root"] = root
    return result


def _limit(delta, best, sign, edge, scale, root):
    """Where the rise of ``-ln L`` reaches :data:`LIMIT_95` beyond ``root`` (towards
    ``edge``): the one-sided 95 % limit; None if it stays below up to the edge."""
    room = abs(edge - best)
    lo, hi = root, root
    d = ONE_SIGMA
    while d < LIMIT_95:
        if abs(hi - best) >= room:
            return None
        lo, hi = hi, best + sign * min(abs(hi - best) * 1.6, room)
        d = delta(hi)
    return _crossing(delta, LIMIT_95, (lo, delta(lo) if lo != root else ONE_SIGMA), (hi, d),
                     0.005 * scale)


def _crossing(delta, level, a, b, xtol):
    """Where ``delta`` reaches ``level`` between ``a = (t, delta(t))`` below it and ``b``
    above: regula falsi (Illinois) on ``sqrt(2 delta)``, which is nearly linear in ``t``
    near a likelihood maximum, so a few evaluations suffice."""
    target = math.sqrt(2 * level)

    def g(d):
        return math.sqrt(2 * max(d, 0.0)) - target

    (ta, fa), (tb, fb) = (a[0], g(a[1])), (b[0], g(b[1]))
    side = 0
    for _ in range(60):
        t = tb - fb * (tb - ta) / (fb - fa) if fb != fa else 0.5 * (ta + tb)
        ft = g(delta(t))
        if abs(ft) < 1e-4 or abs(tb - ta) < xtol:
            return float(t)
        if (ft < 0) == (fa < 0):
            ta, fa = t, ft
            if side == -1:
                fb *= 0.5
            side = -1
        else:
            tb, fb = t, ft
            if side == 1:
                fa *= 0.5
            side = 1
    return float(t)


@dataclass
class ModelComparison:
    """The rigid model (``e_x = 0``) against tangential compliance (``e_x`` free).

    Both are fitted with the same other free parameters, nuisance draws and data. The
    verdict is by BIC (``n`` = number of measured values), which for nested models asks
    the likelihood-ratio statistic to exceed ``ln n`` per extra parameter; AIC and the
    likelihood-ratio test are reported too. ``e_x = 0`` lies on the edge of its range, so
    the ratio's null distribution is the mixture ``chi2_0/2 + chi2_1/2`` (Self & Liang
    1987): ``p = sf_chi2_1(LR) / 2``.
    """

    rigid: FitResult
    compliant: FitResult
    n_points: int

    @property
    def likelihood_ratio(self) -> float:
        """``2 (ln L_compliant - ln L_rigid)``, at least 0."""
        return max(2.0 * (self.rigid.neg_log_likelihood - self.compliant.neg_log_likelihood),
                   0.0)

    @property
    def lr_p_value(self) -> float:
        """p-value of the likelihood ratio under the ``chi2_0/2 + chi2_1/2`` mixture."""
        return 0.5 * float(stats.chi2.sf(self.likelihood_ratio, 1))

    @property
    def delta_aic(self) -> float:
        """AIC(compliant) - AIC(rigid): negative favours tangential compliance."""
        return self.compliant.aic - self.rigid.aic

    @property
    def delta_bic(self) -> float:
        """BIC(compliant) - BIC(rigid): negative favours tangential compliance."""
        return self.compliant.bic(self.n_points) - self.rigid.bic(self.n_points)

    @property
    def preferred(self) -> str:
        """``"compliant"`` or ``"rigid"``: the model with the lower BIC."""
        return "compliant" if self.delta_bic < 0.0 else "rigid"

    def to_dict(self) -> dict:
        """The comparison as JSON-ready data (``model_comparison`` in ``--json``)."""

        def model(r):
            return {"params": {k: {"value": v, "stderr": r.stderr.get(k, math.nan)}
                               for k, v in r.params.items()},
                    "neg_log_likelihood": r.neg_log_likelihood, "aic": r.aic,
                    "bic": r.bic(self.n_points), "chi2": r.chi2, "dof": r.dof,
                    "p_value": r.p_value}

        return _finite({"preferred": self.preferred, "criterion": "BIC",
                "delta_aic": self.delta_aic, "delta_bic": self.delta_bic,
                "likelihood_ratio": self.likelihood_ratio, "lr_p_value": self.lr_p_value,
                "n_points": self.n_points,
                "rigid": model(self.rigid), "compliant": model(self.compliant)})

    def lines(self) -> list[str]:
        """The comparison as printed by ``mcbat fit``, one string per line."""
        e_x = self.compliant.params["e_x"]
        err = self.compliant.stderr["e_x"]
        verdict = ("the data prefer tangential compliance (e_x > 0)"
                   if self.preferred == "compliant" else
                   "the data do not call for tangential compliance (rigid, e_x = 0)")
        return [f"model comparison: {verdict}",
                f"  compliant fit e_x = {e_x:.4g} +- {err:.2g}; delta BIC = "
                f"{self.delta_bic:+.1f}, delta AIC = {self.delta_aic:+.1f} (negative favours "
                f"compliance); likelihood ratio {self.likelihood_ratio:.2f}, "
                f"p = {self.lr_p_value:.3g}"]


def compare_models(study, table, free=("e", "mu"), *, draws=None, seed=0, fitted=None,
                   input_prior=None, likelihood=None):
    """Fit the rigid model (``e_x = 0``) and the compliant one (``e_x`` free) and compare.

    Parameters
    ----------
    study, table, draws, seed, input_prior, likelihood
        As for :func:`fit`.
    free : sequence of str
        The other free parameters, shared by both models (``e_x`` in it is ignored).
    fitted : FitResult, optional
        An existing fit of one of the two models with these ``free`` parameters, reused.

    Returns
    -------
    ModelComparison
    """
    base = [p for p in free if p != "e_x"]
    like_kwargs = dict(draws=draws, seed=seed, input_prior=input_prior, likelihood=likelihood)
    rigid_study = _rigid(study)
    if fitted is not None and "e_x" not in fitted.params and rigid_study:
        rigid = fitted
    elif base:
        rigid = fit(study, table, base, fixed={"e_x": 0.0}, intervals="curvature",
                    **like_kwargs)
    else:  # nothing else free: the rigid model is a single point
        like = Likelihood(study, table, ["e_x"], **like_kwargs)
        nll = like([0.0])
        r = like.residuals([0.0])
        chi2 = like.chi2([0.0])
        rigid = FitResult(params={}, stderr={}, chi2=chi2, dof=int(r.size),
                          p_value=float(stats.chi2.sf(chi2, r.size)),
                          neg_log_likelihood=float(nll), residuals=r)
    if fitted is not None and "e_x" in fitted.params:
        compliant = fitted
    else:
        # Nested: start from the rigid optimum, e_x from a scan along its axis.
        like = Likelihood(study, table, base + ["e_x"], **like_kwargs)
        x_rigid = [rigid.params[p] for p in base]
        scan = np.linspace(*like.search["e_x"], 13)
        e_x0 = scan[int(np.argmin([like([*x_rigid, v]) for v in scan]))]
        compliant = fit(study, table, base + ["e_x"], start=[*x_rigid, e_x0],
                        intervals="curvature", **like_kwargs)
    n_points = int(rigid.residuals.size)
    return ModelComparison(rigid=rigid, compliant=compliant, n_points=n_points)


def _rigid(study):
    """True when the study's own ``e_x`` is 0 (the rigid model)."""
    dist = study.inputs.get("restitution.e_x")
    if dist is not None:
        return dist.family == "fixed" and dist.value == 0.0
    if getattr(study, "kind", None) == "game":  # without [restitution]: the game preset
        return GAME_RESTITUTION.e_x == 0.0
    return True


def _hessian(f, x, bounds, rel=1e-3):
    """Central finite-difference Hessian of ``f`` at ``x``.

    A parameter within a step of an edge of its range (``e_x = 0``, the rigid model, is
    one) gets its stencil shifted inside the range: the curvature one step away.
    """
    n = len(x)
    h = np.maximum(np.abs(x) * rel, 1e-4)
    x = np.array(x, float)
    for i, (lo, hi) in enumerate(bounds):
        x[i] = min(max(x[i], lo + h[i]), hi - h[i])
    hess = np.empty((n, n))
    f0 = f(x)
    for i in range(n):
        for j in range(i, n):
            if i == j:
                xp, xm = x.copy(), x.copy()
                xp[i] += h[i]
                xm[i] -= h[i]
                hess[i, i] = (f(xp) - 2 * f0 + f(xm)) / h[i] ** 2
            else:
                vals = []
                for si, sj in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                    xx = x.copy()
                    xx[i] += si * h[i]
                    xx[j] += sj * h[j]
                    vals.append(f(xx))
                hess[i, j] = hess[j, i] = (vals[0] - vals[1] - vals[2] + vals[3]) / (
                    4 * h[i] * h[j])
    return hess


def _bootstrap(like, best, n, seed):
    """Parametric bootstrap: refit tables simulated at the best fit; std of the refits."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 11,)))
    y_saved = like.y
    fits = []
    try:
        for _ in range(n):
            like.y = like.simulate(best, rng)
            res = optimize.minimize(like, best, method="Nelder-Mead",
                                    options={"xatol": 1e-5, "fatol": 1e-6, "maxiter": 1000})
            fits.append(res.x)
    finally:
        like.y = y_saved
    fits = np.array(fits)
    return dict(zip(like.free, map(float, fits.std(axis=0, ddof=1))))
