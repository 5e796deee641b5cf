"""Fit model parameters to a measurement table, with nuisance scatter marginalised.

Likelihood. Row ``i`` of the table has a measured impact parameter ``b_i`` and incoming spin
``w_i`` (taken as exact), and measured observables ``y_ij`` (exit speed, scattering angle,
outgoing spin) with 1-sigma errors ``s_ij``. The study supplies the fixed setup and the
nuisance scatter (the axial impact point, the spread of the incoming spin, ...): for each
row, ``M`` nuisance draws are solved with the fast kernel at parameters ``theta``, giving
the model's mean ``m_ij(theta)`` and spread ``v_ij(theta)``. The log-likelihood is Gaussian,

    -2 ln L = sum_ij (y_ij - m_ij)^2 / (s_ij^2 + v_ij) + ln(s_ij^2 + v_ij),

with the nuisance draws held fixed (common random numbers) so that ``L`` is smooth in
``theta``. ``scipy.optimize.minimize`` finds the maximum; uncertainties come from the
curvature (a finite-difference Hessian of ``-ln L``) and, optionally, a parametric
bootstrap. ``chi^2`` is the sum of squared normalised residuals at the best fit, with
``dof = rows x observables - free parameters`` and its ``scipy.stats.chi2`` p-value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.dataset.schema import derive
from mcbat.errors import InputError
from mcbat.stats.measurements import OBSERVABLES

__all__ = ["FREE", "FitResult", "GRID_EVALUATIONS", "Likelihood", "ModelComparison", "SEARCH",
           "compare_models", "fit"]

FREE = {"e": (1e-3, 1.0), "mu": (1e-3, 2.0), "ball_inertia_factor": (0.05, 1.0),
        "axial": (-1.0, 1.0), "e_x": (0.0, 1.0)}
"""Parameters that can be fitted, with their allowed ranges (``e_x``: the tangential
restitution of Cross & Nathan 2006, 0 = the rigid model)."""
SEARCH = {"e": (0.05, 0.98), "mu": (0.01, 1.0), "ball_inertia_factor": (0.1, 0.8),
          "axial": (-0.05, 0.05), "e_x": (0.0, 0.6)}
"""Ranges of the coarse grid that starts the search (mu on a logarithmic grid: where
impacts slide, the likelihood changes fast with mu; where all stick it is flat)."""
GRID_EVALUATIONS = 256
"""Size of the coarse starting grid (16 x 16 for two parameters, 6^3 for three, ...)."""
_INDEX = {name: i for i, name in enumerate(INPUT_FIELDS)}
_OUT = {name: i for i, name in enumerate(OUTPUT_FIELDS)}


@dataclass
class FitResult:
    """Best-fit parameters with uncertainties and the goodness of fit."""

    params: dict
    stderr: dict
    chi2: float
    dof: int
    p_value: float
    neg_log_likelihood: float
    bootstrap_stderr: dict = field(default_factory=dict)
    residuals: object = None
    unconstrained: list = field(default_factory=list)
    """Parameters whose likelihood stays flat (within 2 units of -ln L) up to an edge of
    the search range: the data do not bound them, their ``stderr`` is inf."""

    @property
    def aic(self) -> float:
        """Akaike's information criterion, ``2 (-ln L) + 2 k``."""
        return 2.0 * self.neg_log_likelihood + 2.0 * len(self.params)

    def bic(self, n_points: int) -> float:
        """Bayesian information criterion, ``2 (-ln L) + k ln n`` for ``n_points`` values."""
        return 2.0 * self.neg_log_likelihood + len(self.params) * math.log(n_points)

    def to_dict(self) -> dict:
        """The fit as JSON-ready data (the ``mcbat fit --json`` output)."""
        params = {k: {"value": v, "stderr": self.stderr.get(k, math.nan)}
                  for k, v in self.params.items()}
        for k, v in self.bootstrap_stderr.items():
            params[k]["bootstrap_stderr"] = v
        return {"params": params, "chi2": self.chi2, "dof": self.dof,
                "p_value": self.p_value, "aic": self.aic,
                "unconstrained": list(self.unconstrained)}


class Likelihood:
    """``-ln L(theta)`` of a measurement table under a study's model (see module doc)."""

    def __init__(self, study, table, free, draws=48, seed=0, fixed=None):
        unknown = [p for p in free if p not in FREE]
        if unknown:
            raise InputError("free", f"unknown parameter {unknown[0]!r} (choose from "
                             f"{', '.join(FREE)})")
        if not free:
            raise InputError("free", "give at least one parameter to fit")
        for name in ("impact_parameter",):
            if name not in table.columns:
                raise InputError(name, "missing required column",
                                 table.attrs.get("source"))
        self.observables = [c for c in OBSERVABLES if c in table.columns]
        if not self.observables:
            raise InputError(None, f"the table has none of the observables "
                             f"{', '.join(OBSERVABLES)}", table.attrs.get("source"))
        self.free = list(free)
        self.study = study
        rows = len(table)
        self.rows = rows
        self.draws = draws
        # Nuisance draws: the study's own scatter, then each row's measured b and spin.
        cols = study.sample(0, rows * draws, seed)
        inputs = np.stack([np.asarray(cols[n], np.float64) for n in INPUT_FIELDS])
        b = np.repeat(table["impact_parameter"].to_numpy(float), draws)
        from mcbat.core.geometry import angle_from_impact_parameter

        ball_r = inputs[_INDEX["ball_radius"]]
        radius = inputs[_INDEX["bat_radius"]]
        slope = inputs[_INDEX["bat_slope"]]
        inputs[_INDEX["angle"]] = [angle_from_impact_parameter(bb, rr, rad, sl, 0.0)
                                   for bb, rr, rad, sl in zip(b, ball_r, radius, slope)]
        if np.isnan(inputs[_INDEX["angle"]]).any():
            raise InputError("impact_parameter", "beyond the reach of ball and bat: the ball "
                             "would miss", table.attrs.get("source"))
        if "spin_in" in table.columns:
            inputs[_INDEX["ball_wz_in"]] = np.repeat(table["spin_in"].to_numpy(float), draws)
        for name, value in (fixed or {}).items():  # e.g. e_x = 0: the rigid model
            inputs[_INDEX[name]] = value
        self.inputs = inputs
        self.base = {p: inputs[_INDEX[p]].copy() for p in free}
        self.y = np.stack([table[c].to_numpy(float) for c in self.observables], axis=1)
        self.s2 = np.stack([table[f"{c}_err"].to_numpy(float) ** 2 if f"{c}_err" in table
                            else np.full(rows, _default_err(c, self.y[:, j])) ** 2
                            for j, c in enumerate(self.observables)], axis=1)
        self.out = allocate_outputs(rows * draws)
        self.calls = 0

    def predict(self, theta):
        """Model mean and nuisance variance per row and observable, at ``theta``."""
        x = self.inputs
        for name, value in zip(self.free, theta):
            if name == "axial":  # a shift of the impact point, keeping its scatter
                x[_INDEX["axial"]] = self.base["axial"] + value
            else:
                x[_INDEX[name]] = value
        solver = self.study.solver
        out, status, end = self.out
        solve_batch(x, solver["steps"], solver["tolerance"], solver["max_steps"], out, status,
                    end)
        self.calls += 1
        derived = derive([out[_OUT[f"ball_v{c}"]] for c in "xyz"],
                         [out[_OUT[f"ball_w{c}"]] for c in "xyz"])
        values = {"exit_speed": derived["exit_speed"],
                  "scattering_angle": derived["scattering_angle"],
                  "spin_out": derived["spin_axial"]}
        sims = np.stack([values[c].reshape(self.rows, self.draws) for c in self.observables],
                        axis=2)
        return sims.mean(axis=1), sims.var(axis=1, ddof=1)

    def __call__(self, theta):
        """``-ln L`` at the free parameters ``theta`` (1e30 outside their ranges or where
        the likelihood is not finite)."""
        for name, value in zip(self.free, theta):
            lo, hi = FREE[name]
            if not lo <= value <= hi:
                return 1e30
        mean, var = self.predict(theta)
        total = self.s2 + var
        nll = 0.5 * np.sum((self.y - mean) ** 2 / total + np.log(2 * np.pi * total))
        return float(nll) if np.isfinite(nll) else 1e30

    def residuals(self, theta):
        """Normalised residuals ``(measured - model mean) / sigma`` at ``theta``, one row per
        measurement and one column per observable."""
        mean, var = self.predict(theta)
        return (self.y - mean) / np.sqrt(self.s2 + var)


def _default_err(column, values):
    """Without an _err column: 5 % speed, 3 deg angle, 10 % spin (with a 1 rad/s floor)."""
    if column == "exit_speed":
        return 0.05 * np.abs(values)
    if column == "scattering_angle":
        return np.full(len(values), 3.0)
    return np.maximum(0.10 * np.abs(values), 1.0)


def fit(study, table, free=("e", "mu"), *, draws=48, seed=0, bootstrap=0, start=None,
        fixed=None):
    """Maximum-likelihood fit of ``free`` parameters to ``table`` (see the module doc).

    Parameters
    ----------
    study : mcbat.study.Study
        Fixed setup and nuisance scatter.
    table : pandas.DataFrame
        A measurement table (:func:`mcbat.stats.measurements.read_measurements`).
    free : sequence of str
        Parameters to fit, from :data:`FREE`.
    draws : int
        Nuisance draws per row.
    seed : int
        Seed of the nuisance draws (and of the bootstrap).
    bootstrap : int
        Number of parametric bootstrap refits (0: none).
    start : sequence of float, optional
        Starting point; default: the best point of a coarse grid over :data:`SEARCH`.
    fixed : dict, optional
        Inputs held at given values instead of the study's (``{"e_x": 0.0}``: rigid).
    """
    like = Likelihood(study, table, free, draws=draws, seed=seed, fixed=fixed)
    if start is None:
        # The likelihood has flat regions (e.g. every impact sticks above some mu, and then
        # mu does not matter): a coarse grid over the search ranges finds the right basin
        # before the local search.
        points = max(4, round(GRID_EVALUATIONS ** (1.0 / len(like.free))))
        axes = [np.geomspace(*SEARCH[p], points) if p == "mu"
                else np.linspace(*SEARCH[p], points) for p in like.free]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
        x0 = grid[int(np.argmin([like(x) for x in grid]))]
    else:
        x0 = np.asarray(start, float)
    res = optimize.minimize(like, x0, method="Nelder-Mead",
                            options={"xatol": 1e-6, "fatol": 1e-7, "maxiter": 2000})
    best = res.x
    hess = _hessian(like, best, [FREE[p] for p in like.free])
    try:
        cov = np.linalg.inv(hess)
        err = np.sqrt(np.clip(np.diag(cov), 0.0, np.inf))
    except np.linalg.LinAlgError:
        err = np.full(len(best), np.nan)
    # A parameter the data cannot bound (e.g. mu when every impact sticks: above the
    # threshold the likelihood is flat) has no meaningful curvature error: flag it.
    unconstrained = []
    for i, name in enumerate(like.free):
        for edge in SEARCH[name]:
            if edge in FREE[name]:
                continue  # a physical bound (e_x = 0), not the end of the search
            probe = best.copy()
            probe[i] = edge
            if abs(edge - best[i]) > 1e-9 and like(probe) - res.fun < 2.0:
                unconstrained.append(name)
                err[i] = math.inf
                break
    r = like.residuals(best)
    chi2 = float(np.sum(r * r))
    dof = int(r.size - len(best))
    result = FitResult(params=dict(zip(like.free, map(float, best))),
                       stderr=dict(zip(like.free, map(float, err))), chi2=chi2, dof=dof,
                       p_value=float(stats.chi2.sf(chi2, dof)) if dof > 0 else math.nan,
                       neg_log_likelihood=float(res.fun), residuals=r,
                       unconstrained=unconstrained)
    if bootstrap:
        result.bootstrap_stderr = _bootstrap(like, best, bootstrap, seed)
    return result


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

        return {"preferred": self.preferred, "criterion": "BIC",
                "delta_aic": self.delta_aic, "delta_bic": self.delta_bic,
                "likelihood_ratio": self.likelihood_ratio, "lr_p_value": self.lr_p_value,
                "n_points": self.n_points,
                "rigid": model(self.rigid), "compliant": model(self.compliant)}

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


def compare_models(study, table, free=("e", "mu"), *, draws=48, seed=0, fitted=None):
    """Fit the rigid model (``e_x = 0``) and the compliant one (``e_x`` free) and compare.

    Parameters
    ----------
    study, table, draws, seed
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
    like_kwargs = dict(draws=draws, seed=seed)
    rigid_study = "restitution.e_x" not in study.inputs  # the study's own e_x is 0
    if fitted is not None and "e_x" not in fitted.params and rigid_study:
        rigid = fitted
    elif base:
        rigid = fit(study, table, base, fixed={"e_x": 0.0}, **like_kwargs)
    else:  # nothing else free: the rigid model is a single point
        like = Likelihood(study, table, ["e_x"], **like_kwargs)
        nll = like([0.0])
        r = like.residuals([0.0])
        chi2 = float(np.sum(r * r))
        rigid = FitResult(params={}, stderr={}, chi2=chi2, dof=int(r.size),
                          p_value=float(stats.chi2.sf(chi2, r.size)),
                          neg_log_likelihood=float(nll), residuals=r)
    if fitted is not None and "e_x" in fitted.params:
        compliant = fitted
    else:
        # Nested: start from the rigid optimum, e_x from a scan along its axis.
        like = Likelihood(study, table, base + ["e_x"], **like_kwargs)
        x_rigid = [rigid.params[p] for p in base]
        scan = np.linspace(*SEARCH["e_x"], 13)
        e_x0 = scan[int(np.argmin([like([*x_rigid, v]) for v in scan]))]
        compliant = fit(study, table, base + ["e_x"], start=[*x_rigid, e_x0], **like_kwargs)
    n_points = int(rigid.residuals.size)
    return ModelComparison(rigid=rigid, compliant=compliant, n_points=n_points)


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
    mean, var = like.predict(best)
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 11,)))
    y_saved = like.y
    fits = []
    try:
        for _ in range(n):
            like.y = mean + np.sqrt(like.s2 + var) * rng.standard_normal(mean.shape)
            res = optimize.minimize(like, best, method="Nelder-Mead",
                                    options={"xatol": 1e-5, "fatol": 1e-6, "maxiter": 1000})
            fits.append(res.x)
    finally:
        like.y = y_saved
    fits = np.array(fits)
    return dict(zip(like.free, map(float, fits.std(axis=0, ddof=1))))
