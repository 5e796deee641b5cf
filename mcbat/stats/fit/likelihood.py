"""The likelihood of a measurement table under a study's model, marginalising nuisance
scatter and the errors of the measured inputs (``mcbat.stats.fit.estimate.fit`` maximises it).
Row ``i`` of the table has measured inputs (a drop test's impact parameter
``b_i`` and incoming spin; a game's bat speed, attack angle, undercut, ...) and measured
observables ``y_i`` (exit speed, scattering angle, outgoing spin; or launch speed, launch
angle, spin rate, ...) with 1-sigma errors ``s_i`` (the ``_err`` columns; an observable
without one gets one error for all rows,
``mcbat.stats.measurements.default_errors``). For each row, ``M`` draws
are solved with the fast kernel at parameters ``theta`` (``mcbat.stats.models.draws`` builds
them):

* the study's nuisance scatter (the impact point, the spread of the incoming spin when
  the table has no ``spin_in``, ...) is drawn from the study;
* a measured input with an ``_err`` column is drawn from its posterior given the
  measurement (a prior of the true values estimated from the table, times a normal of the
  stated width about the measured value, within the range the study allows for that
  input: ``mcbat.stats.models.input_priors``), stratified over the ``M`` draws (one draw in each of
  ``M`` equal-probability slices) so that the smear is represented with little Monte Carlo
  noise; without an ``_err`` column the input is exact. With the mixture likelihood, half
  of a drop test's draws are then moved near each row's posterior given the observables
  too, with importance weights (``Likelihood.refine``): the observables fix a row's
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
  ``draw_moments``),

      -2 ln L_i = r_i^T T_i^-1 r_i + ln det(2 pi T_i),  r_i = y_i - m_i,
      T_i = diag(s_i^2) + C_i.

  The default of a game, whose draws spread over several unmeasured inputs (the swing,
  the contact): there ``M`` draws resolve a mean and a covariance but not a density.

The draws are held fixed (common random numbers), so ``L`` is smooth in ``theta``. An
observable far outside what the model gives over the search grid (a wrong unit) is refused
(``mcbat.stats.fit.unit_guard``).
"""

from __future__ import annotations

import math

import numpy as np

from mcbat.checks import check_count
from mcbat.core.status import OK, STATUS_NAMES
from mcbat.errors import InputError
from mcbat.stats.measurements import default_errors
from mcbat.stats.models.draws import BatFrameModel, GameModel, rows_text
from mcbat.stats.models.flight import FlightModel
from mcbat.stats.models.input_priors import INPUT_PRIORS, PRIOR_RIDGE, PriorFamily

__all__ = ["FREE", "LIKELIHOODS", "Likelihood", "SEARCH", "check_free", "draw_model",
           "draw_moments"]

FREE = {"e": (1e-3, 1.0), "mu": (1e-3, 2.0), "ball_inertia_factor": (0.05, 1.0),
        "axial": (-1.0, 1.0), "e_x": (0.0, 1.0), "drag_scale": (0.2, 3.0),
        "lift_scale": (0.0, 3.0)}
"""Parameters that can be fitted, with their allowed ranges (``e_x``: the tangential
restitution of Cross & Nathan 2006, 0 = the rigid model; ``drag_scale``, ``lift_scale``:
the flight model's, ``mcbat.stats.models.flight``)."""
SEARCH = {"e": (0.05, 0.98), "mu": (0.01, 1.0), "ball_inertia_factor": (0.1, 0.8),
          "axial": (-0.05, 0.05), "e_x": (0.0, 0.6), "drag_scale": (0.5, 1.5),
          "lift_scale": (0.0, 2.0)}
"""Ranges of the coarse grid that starts the search (mu on a logarithmic grid: where
impacts slide, the likelihood changes fast with mu; where all stick it is flat)."""
LIKELIHOODS = ("mixture", "gaussian")
"""The forms of a row's likelihood (module docstring)."""
BAD_NLL = 1e30
"""``-ln L`` of a point the model cannot evaluate (outside the ranges, too few good draws):
finite, so that the optimisers step back from it."""


def check_free(free):
    """``free`` as a list of known, distinct parameter names, or ``InputError``."""
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


class Likelihood:
    """``-ln L(theta)`` of a measurement table under a study's model (see module doc).

    Parameters
    ----------
    study : mcbat.study.Study or mcbat.study.game.GameStudy
        Fixed setup and nuisance scatter. A bat-frame study must place the contact by
        ``contact.impact_parameter`` (the ball's line offset from the bat axis).
    table : pandas.DataFrame
        Measurement table (``mcbat.stats.models.draws`` lists the columns of each kind of
        study, with their units): measured inputs, observables and ``_err`` columns
        (1 sigma, same units; an observable without one gets ``default_errors``).
    free : sequence of str
        Parameters to fit, from ``FREE`` (the game model has ``e``, ``mu``, ``e_x``).
    draws : int, optional
        Draws per row (at least 4; default 48 for a drop test, 128 for a game:
        ``mcbat.stats.models.draws.GameModel.DEFAULT_DRAWS`` says why).
    seed : int
        Seed of the draws.
    fixed : dict, optional
        Parameters held at given values (``{"e_x": 0.0}``: the rigid model).
    input_prior : {"cover", "widen", "study"}, optional
        The range the true values of an input with an ``_err`` column are marginalised
        over (``mcbat.stats.models.draws``): ``"cover"`` the study's range widened to cover
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
        draws = None if draws is None else check_count(draws, "draws", 4)
        seed = check_count(seed, "seed", 0)
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
        """The coarse grid's ranges for this study's model (``SEARCH``, narrowed by
        the model's own)."""
        self.y = np.stack([table[c].to_numpy(float) for c in self.observables], axis=1)
        self.s2 = np.stack([table[f"{c}_err"].to_numpy(float) ** 2 if f"{c}_err" in table
                            else default_errors(c, self.y[:, j]) ** 2
                            for j, c in enumerate(self.observables)], axis=1)
        self.stated_errors = [f"{c}_err" for c in self.observables if f"{c}_err" in table]
        """The observables' ``_err`` columns the table gives (the others get
        ``default_errors``)."""
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
        ``mcbat.stats.models.input_priors.PRIOR_DEGREE`` per measured input in
        ``prior_families``)."""

    def predict(self, theta):
        """Model mean and covariance per row at ``theta``, or None (and the reason in
        ``failure``) when some row has fewer than two good draws.

        Returns
        -------
        mean : ndarray, (rows, observables)
            Mean over the good draws (units of the observables).
        cov : ndarray, (rows, observables, observables)
            The draws' covariance plus the Monte Carlo error of their mean
            (``draw_moments``).
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
        log_density = self._draw_log_density(sims, ok)
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

    def _draw_log_density(self, sims, ok):
        """``ln N(y_i; sims_ik, diag(s2_i))`` up to a constant, plus the draws' own log
        weights (``mcbat.stats.models.draws._DrawModel.draw_log_weight``); -inf for a bad
        draw. Shape (rows, draws)."""
        log_density = -0.5 * ((self.y[:, None, :] - sims) ** 2 / self.s2[:, None, :]).sum(axis=2)
        if self.model.draw_log_weight is not None:
            log_density = log_density + self.model.draw_log_weight
        return np.where(ok, log_density, -np.inf)

    @property
    def last_draws(self):
        """``(sims, ok)`` of the last evaluation: each row's draws of the observables
        (rows, draws, observables) and whether each draw is good (rows, draws); None
        before the first."""
        return self._draws

    def posterior_log_weights(self, theta):
        """Log weights (rows, draws; -inf for a bad draw) of each row's draws at ``theta``,
        as the likelihood weighs them: with the mixture likelihood, the draws' posterior
        given the row's observables under the prior fitted at ``theta``; with the normal
        form, every good draw the same. None when ``theta`` cannot be evaluated.

        Leaves ``last_draws`` at ``theta``."""
        if self._evaluate(theta) is None:
            return None
        sims, ok = self._draws
        if self.likelihood != "mixture":
            return np.where(ok, 0.0, -np.inf)
        log_w = self._draw_log_density(sims, ok)
        if self._prior_basis is not None:
            log_w = log_w + self._prior_basis @ self.prior_coefficients
        return log_w

    def refine(self, theta):
        """With the mixture likelihood, place half of each row's draws of a smeared measured
        input near its posterior given the observables at ``theta`` (a point near the best
        fit: ``mcbat.stats.models.draws.BatFrameModel.refine_draws``), and rebuild the
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
                return BAD_NLL
        got = self._evaluate(theta)
        if got is None:
            return BAD_NLL
        nll, _, total, mean = got
        if self.envelope is not None:  # the range of predictions over the search grid
            lo, hi, sd, med_lo, med_hi = self.envelope
            np.minimum(lo, mean, out=lo)
            np.maximum(hi, mean, out=hi)
            np.maximum(sd, np.sqrt(np.diagonal(total, axis1=1, axis2=2)), out=sd)
            med = np.median(mean, axis=0)
            np.minimum(med_lo, med, out=med_lo)
            np.maximum(med_hi, med, out=med_hi)
        return nll if math.isfinite(nll) else BAD_NLL

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
        """An ``InputError`` saying which rows could not be evaluated, and why."""
        bad, status, theta = self.failure
        where = ", ".join(f"{k} = {v:.4g}" for k, v in theta.items())
        hints = {"max_steps": (None, " (the solver's step budget: raise [solver] max_steps)"),
                 **self.model.FAILURE_HINTS}
        column, hint = hints.get(status, (None, ""))
        return InputError(column, f"the likelihood cannot be evaluated: {rows_text(bad)} "
                          f"({int(bad.sum())} of {self.rows}) have no good impact among their "
                          f"{self.draws} draws (status {status}{hint}) at {where}",
                          self.source)


def draw_model(study, table, draws, seed, fixed=None, input_prior=None, likelihood=None):
    """The draw model of ``study`` (``mcbat.stats.models.draws.GameModel``,
    ``mcbat.stats.models.draws.BatFrameModel`` or
    ``mcbat.stats.models.flight.FlightModel``); ``draws`` None: the model's
    ``DEFAULT_DRAWS``; ``input_prior`` None: ``"cover"`` for the mixture likelihood
    (``likelihood``, default the model's), which estimates the prior, else ``"widen"``."""
    if input_prior is not None and input_prior not in INPUT_PRIORS:
        raise InputError("input_prior", f"must be one of {', '.join(INPUT_PRIORS)}, got "
                         f"{input_prior!r}")
    kind = getattr(study, "kind", None)
    if kind == "flight":
        # A flight table has no measured inputs with errors: no prior to choose.
        return FlightModel(study, table, FlightModel.DEFAULT_DRAWS if draws is None else draws,
                           seed, fixed)
    cls = GameModel if kind == "game" else BatFrameModel
    form = likelihood or cls.LIKELIHOOD
    if input_prior is None:
        input_prior = "cover" if form == "mixture" else "widen"
    elif input_prior == "cover" and form != "mixture":
        raise InputError("input_prior", "'cover' needs the mixture likelihood (the normal "
                         "one cannot estimate the prior's step at the study's range)")
    return cls(study, table, cls.DEFAULT_DRAWS if draws is None else draws, seed, fixed,
               input_prior)


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
        (``mcbat.stats.models.draws``), so neighbours lie in neighbouring slices and ``V`` is
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
