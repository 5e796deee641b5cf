"""Intervals of a fit: profile likelihood, one-sided limits, curvature and bootstrap errors.

A profile-likelihood interval ends where ``-ln L``, minimised over the other parameters,
rises by ``ONE_SIGMA`` above its minimum; on a side where it stays flat up to the end
of the parameter's range, a one-sided 95 % limit (a rise of ``LIMIT_95``) is given
instead, and a side that ends at a physical edge (``PHYSICAL_EDGES``) ends the interval
there. Each function takes the likelihood (``mcbat.stats.fit.likelihood.Likelihood``) and
the best fit.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Mapping
from typing import Any, Literal

import numpy as np
from scipy import optimize, stats

from mcbat.stats.fit.likelihood import FREE
from mcbat.stats.fit.selective import conditional_limit

__all__ = ["LIMIT_95", "ONE_SIGMA", "PHYSICAL_EDGES", "RISE_95", "Interval", "IntervalStatus",
           "bootstrap_errors", "curvature_errors", "flat_to_edge", "hessian",
           "profile_intervals"]

PHYSICAL_EDGES = {("e", 1.0), ("e_x", 0.0), ("e_x", 1.0), ("mu", 1e-3), ("e", 1e-3),
                  ("lift_scale", 0.0)}
"""Ends of ``FREE`` that are physical limits (an interval may end there); the other
ends (``mu = 2``, ...) only end the search, and a likelihood still flat there means the data
do not bound the parameter on that side."""
ONE_SIGMA = 0.5
"""Rise of ``-ln L`` that ends a 68.3 % profile-likelihood interval."""
LIMIT_95 = 0.5 * stats.chi2.ppf(0.90, 1)
"""Rise of ``-ln L`` (1.353) that sets a one-sided 95 % limit."""
RISE_95 = 0.5 * stats.chi2.ppf(0.95, 1)
"""Rise of ``-ln L`` (1.921) that ends a two-sided 95 % profile interval."""

IntervalStatus = Literal["measured", "lower_limit", "upper_limit", "unidentified",
                         "profile_failed"]
"""What a profile-likelihood interval says about its parameter (``Interval.status``)."""


@dataclasses.dataclass(frozen=True)
class Interval(Mapping[str, Any]):
    """The profile-likelihood result of one fitted parameter (``FitResult.intervals``).

    Parameters
    ----------
    lower_error, upper_error : float or None
        Distances (parameter units, >= 0) from the best value down and up to where
        ``-ln L`` has risen by ``ONE_SIGMA``; None on a side the data do not bound.
    status : {"measured", "lower_limit", "upper_limit", "unidentified", "profile_failed"}
        ``"measured"``: a two-sided interval; ``"lower_limit"`` / ``"upper_limit"``: the
        data bound the parameter on one side only (``limit``); ``"unidentified"``: on
        neither; ``"profile_failed"``: the profile jumps at the best fit, no interval.
    limit : float or None
        The one-sided 95 % limit (parameter units), or None.
    at_bound : float or None
        The physical edge of the parameter's range (``PHYSICAL_EDGES``) the interval
        reaches, or None.
    limit_kind : {"conditional", "likelihood_ratio"} or None
        How a one-sided ``limit`` was found: conditional on the profile being flat
        (``mcbat.stats.fit.selective``) or from the likelihood ratio alone; None for no limit.
    open_at_95 : float or None
        For a measured parameter: the end of its range (not a physical edge) where the
        likelihood still lies within the 95 % level of its best value, else None.

    Notes
    -----
    An ``Interval`` also reads as a read-only mapping with the keys of ``to_dict()``
    (``iv["lower_error"]``, ``iv.get("limit_kind")``), kept for code written when the
    intervals were plain dictionaries.
    """

    lower_error: float | None
    upper_error: float | None
    status: IntervalStatus
    limit: float | None = None
    at_bound: float | None = None
    limit_kind: Literal["conditional", "likelihood_ratio"] | None = None
    open_at_95: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """The interval as JSON-ready data (the entries of ``mcbat fit --json``'s
        ``params``): ``limit_kind`` and ``open_at_95`` only where they are set."""
        out: dict[str, Any] = {"lower_error": self.lower_error,
                               "upper_error": self.upper_error, "status": self.status,
                               "limit": self.limit, "at_bound": self.at_bound}
        if self.limit_kind is not None:
            out["limit_kind"] = self.limit_kind
        if self.open_at_95 is not None:
            out["open_at_95"] = self.open_at_95
        return out

    def __getitem__(self, key: str) -> Any:
        return self.to_dict()[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self.to_dict())

    def __len__(self) -> int:
        return len(self.to_dict())


def curvature_errors(like, best):
    """Curvature errors and covariance (NaN where the Hessian is not positive definite)."""
    hess = hessian(like, best, [FREE[p] for p in like.free])
    n = len(best)
    try:
        np.linalg.cholesky(hess)
        cov = np.linalg.inv(hess)
        return np.sqrt(np.diag(cov)), cov
    except np.linalg.LinAlgError:
        diag = np.diag(hess)
        err = np.where(diag > 0, 1.0 / np.sqrt(np.abs(diag)), np.nan)
        return err, np.full((n, n), np.nan)


def flat_to_edge(like, best, nll_min):
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


def profile_intervals(like, best, nll_min, err, cov, seed=0):
    """Profile-likelihood intervals of every free parameter.

    Returns the per-parameter summary (``FitResult.intervals``) and a better point if
    the profile found one (``-ln L`` lower than at ``best`` by more than 1e-3), else None.
    A one-sided limit is the one conditional on the profile being flat on the other side
    (``mcbat.stats.fit.selective``, its simulated tables seeded by ``seed``), or the
    likelihood-ratio limit where that cannot be computed (``limit_kind`` says which).
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
    last = {}

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
        last["x"] = x.copy()
        return value - nll_min

    def point(i, t):
        """The profile's point (every free parameter) at parameter i = t."""
        profile(i, t)
        return last["x"]

    summary = {}
    for i, name in enumerate(like.free):
        lo_edge, hi_edge = FREE[name]
        sides = {}
        for sign, edge in ((-1, lo_edge), (1, hi_edge)):
            sides[sign] = _side(lambda t, i=i: profile(i, t), best[i], sign, edge,
                                scale[i], (name, edge) in PHYSICAL_EDGES)
        entry = _entry(sides[-1], sides[1], lambda sign, side, i=i: _limit(
            lambda t: profile(i, t), best[i], sign, side["edge"], scale[i], side["root"]))
        summary[name] = _complete(entry, sides, like, best, i, lambda t, i=i: profile(i, t),
                                  lambda t, i=i: point(i, t), seed)
    return summary, found["x"]


def _complete(entry, sides, like, best, i, rise, point, seed):
    """Add to parameter ``i``'s entry what its two sides alone do not give: the end of the
    range its 95 % region reaches (``open_at_95``), and a one-sided limit conditional on
    the flat side (``mcbat.stats.fit.selective``). ``rise(t)`` is the profile's rise at
    ``t``, ``point(t)`` its point there. Returns the completed entry."""
    name = like.free[i]
    if entry.status == "measured":
        # A 68 % interval can end below a plateau that the 95 % level still reaches (a
        # drop-test table whose drops all stick, with one row that looks as if it slid):
        # say so rather than let the interval stand for a measurement at 95 %.
        for sign in (-1, 1):
            edge = sides[sign]["edge"]
            if (sides[sign]["error"] is not None and (name, edge) not in PHYSICAL_EDGES
                    and abs(edge - best[i]) > 1e-9 and rise(edge) < RISE_95):
                entry = dataclasses.replace(entry, open_at_95=edge)
    if entry.status in ("lower_limit", "upper_limit") and entry.limit is not None:
        sign, side = (-1, sides[-1]) if entry.status == "lower_limit" else (1, sides[1])
        entry = dataclasses.replace(entry, limit_kind="likelihood_ratio")
        if side["root"] is not None:
            limit = conditional_limit(like, best, i, sign, point, entry.limit, side["root"],
                                      sides[-sign]["edge"], seed, ONE_SIGMA)
            if limit is not None:
                entry = dataclasses.replace(entry, limit=limit, limit_kind="conditional")
    return entry


def _entry(lower, upper, limit):
    """The ``FitResult.intervals`` entry (``Interval``) of one parameter from its two
    sides; ``limit(sign, side)`` computes a one-sided 95 % limit."""
    if lower.get("failed") or upper.get("failed"):
        return Interval(lower_error=None, upper_error=None, status="profile_failed")
    at_bound = None
    for side in (lower, upper):
        if side["physical"]:
            at_bound = side["edge"]
    status, bound = "measured", None
    if lower["error"] is None and upper["error"] is None:
        status = "unidentified"
    elif upper["error"] is None or lower["error"] is None:
        sign, side = (-1, lower) if upper["error"] is None else (1, upper)
        status = "lower_limit" if sign < 0 else "upper_limit"
        # The bounded side's 95 % limit, or the physical edge its interval reaches.
        bound = limit(sign, side) if side["root"] is not None else side["edge"]
    return Interval(lower_error=lower["error"], upper_error=upper["error"], status=status,
                    limit=bound, at_bound=at_bound)


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
    """Where the rise of ``-ln L`` reaches ``LIMIT_95`` beyond ``root`` (towards
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


def hessian(f, x, bounds, rel=1e-3):
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


def bootstrap_errors(like, best, n, seed):
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
