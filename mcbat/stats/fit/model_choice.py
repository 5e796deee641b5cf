"""Model comparison: the rigid model (``e_x = 0``) against the tangentially compliant one,
fitted to the same table, by likelihood ratio, AIC and BIC."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from mcbat.bodies.restitution import GAME_RESTITUTION
from mcbat.stats.fit.estimate import FitResult, finite, fit
from mcbat.stats.fit.likelihood import Likelihood

__all__ = ["ModelComparison", "compare_models"]

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

        return finite({"preferred": self.preferred, "criterion": "BIC",
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
        error = f" +- {err:.2g}" if math.isfinite(err) else " (no error: the data do not " \
            "constrain it)"
        return [f"model comparison: {verdict}",
                f"  compliant fit e_x = {e_x:.4g}{error}; delta BIC = "
                f"{self.delta_bic:+.1f}, delta AIC = {self.delta_aic:+.1f} (negative favours "
                f"compliance); likelihood ratio {self.likelihood_ratio:.2f}, "
                f"p = {self.lr_p_value:.3g}"]


def compare_models(study, table, free=("e", "mu"), *, draws=None, seed=0, fitted=None,
                   input_prior=None, likelihood=None):
    """Fit the rigid model (``e_x = 0``) and the compliant one (``e_x`` free) and compare.

    Parameters
    ----------
    study, table, draws, seed, input_prior, likelihood
        As for ``fit``.
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
