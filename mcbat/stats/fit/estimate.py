"""Maximum-likelihood fit of model parameters to a measurement table.

``mcbat.stats.fit.likelihood.Likelihood`` gives ``-ln L`` of the table at any parameters,
marginalising the nuisance scatter and the errors of the measured inputs. ``fit``
finds its maximum (a coarse grid, fine scans in ``mu`` and Nelder-Mead:
``mcbat.stats.fit.search``) and the intervals (``mcbat.stats.fit.intervals``):
profile-likelihood intervals, where ``-ln L`` rises by 1/2 when the other parameters are
re-optimised (asymmetric in general); where the likelihood stays flat up to the end of a
parameter's range on one side, a one-sided 95 % limit (a rise of 1.353) instead, and a
parameter flat on both sides is reported as not identified. The curvature error
(finite-difference Hessian) is kept as ``stderr``; a parametric bootstrap is optional. The
goodness of fit is the normal form's ``chi^2 = sum_i r_i^T T_i^-1 r_i`` at the best fit
(for either likelihood), with ``dof = rows x observables - free parameters`` and its
``scipy.stats.chi2`` p-value. ``FitResult.warnings`` says what a user must hear (a
best value at a search bound or far from the study's preset, a p-value implausibly close to
1, a measured input beyond the study's range).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from mcbat.errors import InputError
from mcbat.stats.fit.intervals import (
    PHYSICAL_EDGES,
    Interval,
    bootstrap_errors,
    curvature_errors,
    flat_to_edge,
    profile_intervals,
)
from mcbat.stats.fit.likelihood import FREE, SEARCH, Likelihood
from mcbat.stats.fit.search import local_minimum, search, search_scale
from mcbat.stats.measurements import measured_fraction

__all__ = ["FREE", "FitResult", "Likelihood", "SEARCH", "check_bootstrap", "fit"]

SHARE_BEYOND_WARNING = 0.05
"""A fit warns when the fitted prior of a measured input puts this share or more of the
true values beyond the study's range (or when the measured values reject that range)."""
P_VALUE_TOO_GOOD = 0.995
"""A chi-squared p-value above this is reported: the stated errors are larger than the
scatter of the data (or a column is in another unit)."""
PRESET_DEVIATION = 0.4
"""``e`` further than this fraction from the study's own value is reported (a baseball's
``e*`` is known to a few per cent; a fit far from it usually means a unit or a column is
wrong)."""


@dataclass
class FitResult:
    """Best-fit parameters with uncertainties and the goodness of fit.

    ``stderr`` holds the curvature errors (``inf`` for a parameter the data do not bound,
    NaN where the curvature is not positive); ``intervals`` the profile-likelihood result
    per parameter (``mcbat.stats.fit.intervals.Interval``): ``lower_error``, ``upper_error``
    (positive, or None on a side the data do not bound), ``status`` (``"measured"``,
    ``"lower_limit"``, ``"upper_limit"`` or ``"unidentified"``, or ``"profile_failed"``
    when the profile jumps at the best fit and no interval can be given: its ``stderr``
    is then still the curvature error, which describes the likelihood only near the best
    fit), ``limit`` (the one-sided 95 % limit, or None; ``limit_kind`` says how:
    ``"conditional"`` on the profile being flat, ``mcbat.stats.fit.selective``, or
    ``"likelihood_ratio"``) and ``at_bound`` (the physical edge the interval reaches, or
    None); a measured parameter whose likelihood at the end of its range (not a physical
    edge) rises less than the 95 % level above the best fit has that end as
    ``open_at_95`` (and a warning).
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
    intervals: dict[str, Interval] = field(default_factory=dict)
    priors: dict = field(default_factory=dict)
    """Measured input -> the flat prior its true values were marginalised over
    (``mcbat.stats.models.draws._DrawModel.priors``: ``study_range``, ``range``, ``widened``,
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
            if k in self.intervals:
                entry.update(self.intervals[k].to_dict())
            if k in self.bootstrap_stderr:
                entry["bootstrap_stderr"] = self.bootstrap_stderr[k]
            params[k] = entry
        return finite({"params": params, "chi2": self.chi2, "dof": self.dof,
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
                if lo is None and math.isfinite(self.stderr.get(name, math.nan)):
                    out.append(f"  {name} = {value:.6g} +- {self.stderr[name]:.2g} "
                               f"(curvature{extra})")
                elif lo is None:
                    out.append(f"  {name} = {value:.6g} (no error: the data do not constrain "
                               f"it{extra})")
                else:
                    out.append(f"  {name} = {value:.6g} -{lo:.2g} +{hi:.2g} (68 % profile "
                               f"likelihood{edge}; {curv}{extra})")
            elif status == "profile_failed":
                out.append(f"  {name} = {value:.6g}: the profile likelihood could not be "
                           f"computed (it jumps at the best fit), so no interval is given; "
                           f"{curv} describes the likelihood only near the best fit{extra}")
            elif status in ("lower_limit", "upper_limit"):
                sign, side = (">", "above") if status == "lower_limit" else ("<", "below")
                given = (", conditional on the flat likelihood"
                         if iv.get("limit_kind") == "conditional" else "")
                out.append(f"  {name} {sign} {iv['limit']:.4g} (95 % CL{given}; the data do "
                           f"not bound {name} from {side}: best value {value:.4g} is not a "
                           f"measurement)")
            else:
                lo, hi = FREE[name]
                out.append(f"  {name}: not identified by the data (the likelihood is flat "
                           f"over {lo:g}..{hi:g}; {value:.4g} is not a measurement)")
        return out


def finite(obj):
    """``obj`` with every non-finite float replaced by None (strict JSON)."""
    if isinstance(obj, dict):
        return {k: finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def check_bootstrap(n):
    """``n`` refits: 0 (none) or at least 2 (a spread needs two), or ``InputError``."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not (n == 0 or n >= 2):
        raise InputError("bootstrap", f"must be 0 (no bootstrap) or an integer >= 2, got {n!r}")
    return int(n)


def fit(study, table, free=("e", "mu"), *, draws=None, seed=0, bootstrap=0, start=None,
        fixed=None, intervals="profile", input_prior=None, likelihood=None):
    """Maximum-likelihood fit of ``free`` parameters to ``table`` (see the module doc).

    Parameters
    ----------
    study : mcbat.study.Study
        Fixed setup and nuisance scatter.
    table : pandas.DataFrame
        A measurement table (``mcbat.stats.measurements.read_measurements``).
    free : sequence of str
        Parameters to fit, from ``FREE`` (distinct).
    draws : int, optional
        Draws per row (nuisance scatter and measured-input errors; default: the model's,
        48 for a drop test, 128 for a game).
    seed : int
        Seed of the draws (and of the bootstrap).
    bootstrap : int
        Number of parametric bootstrap refits (0: none, else at least 2).
    start : sequence of float, optional
        Starting point; default: the best point of a coarse grid over ``SEARCH``.
    fixed : dict, optional
        Inputs held at given values instead of the study's (``{"e_x": 0.0}``: rigid).
    intervals : {"profile", "curvature"}
        ``"profile"``: profile-likelihood intervals and limits (``FitResult.intervals``);
        ``"curvature"``: the Hessian errors only (faster).
    input_prior : {"cover", "widen", "study"}, optional
        See ``Likelihood``; the prior used is in ``FitResult.priors``.
    likelihood : {"mixture", "gaussian"}, optional
        See ``Likelihood`` (default: the model's).

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
    res = search(like, start)
    best, nll_min = res.x, float(res.fun)
    err, cov = curvature_errors(like, best)
    summary = {}
    if intervals == "profile":
        summary, better = profile_intervals(like, best, nll_min, err, cov, seed)
        if better is not None:  # the profile found a lower point: restart from it
            res = local_minimum(like, better, search_scale(like))
            best, nll_min = res.x, float(res.fun)
            err, cov = curvature_errors(like, best)
            summary, _ = profile_intervals(like, best, nll_min, err, cov, seed)
        unconstrained = [p for p in like.free
                         if summary[p]["status"] not in ("measured", "profile_failed")]
    else:
        unconstrained = flat_to_edge(like, best, nll_min)
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
        result.bootstrap_stderr = bootstrap_errors(like, best, bootstrap, seed)
    return result


def _warnings(like, result):
    """The sentences of ``FitResult.warnings``."""
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
        edge = result.intervals.get(name, {}).get("open_at_95")
        if edge is not None:
            side = "above" if edge > value else "below"
            out.append(f"{name}: the 68 % interval is two-sided, but the likelihood at the end "
                       f"of the range ({name} = {edge:g}) lies within the 95 % level of its "
                       f"best value: at 95 % the data do not bound {name} from {side}")
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
    for j, name in enumerate(like.observables):
        if f"{name}_err" not in like.stated_errors:
            continue
        errors = np.sqrt(like.s2[:, j])
        share = measured_fraction(like.y[:, j], errors)
        if share is not None:
            unit, pct = like.units[name], f"{100 * share:.3g} %"
            mean = share * float(np.mean(np.abs(like.y[:, j])))
            one = max(mean, float(errors.min()))
            which = f"{pct} of the mean" if one == mean else "the smallest stated error"
            out.append(f"{name}_err is {pct} of each row's measured {name}: an error stated "
                       f"from the measured value gives the rows measured high less weight "
                       f"and biases the fit, by more of its errors the more rows "
                       f"(docs/fit-checks.md); state one error for all rows ({which}: "
                       f"{one:.4g} {unit}) or the instrument's own")
    if math.isfinite(result.p_value) and result.p_value > P_VALUE_TOO_GOOD:
        out.append(f"the fit is implausibly good (p-value {result.p_value:.4f}): the stated "
                   f"errors are larger than the scatter of the data, or a column is in "
                   f"another unit")
    return out
