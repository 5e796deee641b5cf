"""The search for the maximum of a fit's likelihood: a coarse grid, fine scans in ``mu``
and Nelder-Mead.

The likelihood of a drop test has flat regions (every impact sticks above some ``mu``, and
then ``mu`` does not matter) and valleys narrower than the grid's spacing just below them:
the grid finds the basin, a fine line and a profile scan in ``mu`` find the valley, and
local searches from both settle in it (``search``).
"""

from __future__ import annotations

import numpy as np
from scipy import optimize

from mcbat.errors import InputError
from mcbat.stats.fit.likelihood import BAD_NLL, FREE
from mcbat.stats.fit.unit_guard import check_units

__all__ = ["FINE_SIMPLEX", "GRID_EVALUATIONS", "SCAN_POINTS", "STARTS", "local_minimum",
           "search", "search_scale"]

GRID_EVALUATIONS = 121
"""Size of the coarse starting grid (11 x 11 for two parameters; at least 6 points a
parameter: 6^3 for three, ...)."""
STARTS = 2
"""Local searches from the best points of the grid (plus one from the profile scan in mu,
``SCAN_POINTS``)."""
SCAN_POINTS = 48
"""Values of mu (log-spaced over its search range, 10 % apart) at which the profile is
scanned for the start of the local search."""
FINE_SIMPLEX = 20.0
"""A local search from a fine scan's point starts with a simplex this many times smaller
than one from the coarse grid."""


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


def local_minimum(like, x0, scale):
    """Nelder-Mead from ``x0`` with a simplex of ``scale`` (tolerances well below any error)."""
    simplex = np.vstack([x0] + [x0 + np.eye(len(x0))[i] * scale[i] *
                                (1 if x0[i] + scale[i] <= FREE[p][1] else -1)
                                for i, p in enumerate(like.free)])
    return optimize.minimize(like, x0, method="Nelder-Mead",
                             options={"xatol": 1e-5, "fatol": 1e-5, "maxiter": 4000,
                                      "initial_simplex": simplex})


def search(like, start=None):
    """The best fit of ``like``: an ``scipy.optimize.OptimizeResult`` (``x``, ``fun``).

    Parameters
    ----------
    like : mcbat.stats.fit.likelihood.Likelihood
        The likelihood; its draws are refined near the best point of the coarse grid (or
        at ``start``).
    start : sequence of float, optional
        Starting point; default: the best points of a coarse grid over ``like.search``.

    Raises
    ------
    InputError
        When no point of the grid can be evaluated, an observable lies far outside what the
        model gives (``mcbat.stats.fit.unit_guard.check_units``), or
        ``start`` cannot be evaluated.
    """
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
        if not (values < BAD_NLL).any():
            raise like.failure_error()
        check_units(like)
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
        if not like(starts[0]) < BAD_NLL:
            raise like.failure_error() if like.failure else InputError(
                "start", f"outside the parameter ranges: {list(starts[0])}")
    scale = search_scale(like)
    # Local searches from the best grid points: the likelihood can have a second basin
    # (e.g. every drop stuck at large mu, with e_x = 0) that one start would settle in.
    # A start from a fine scan sits in a valley that may be narrower than the coarse
    # simplex (a few percent wide in mu): its search starts with a simplex of a twentieth
    # of the size, which stays in the valley instead of stepping over it onto the plateau.
    res = min([local_minimum(like, x0, scale) for x0 in starts]
              + [local_minimum(like, x0, scale / FINE_SIMPLEX) for x0 in fine],
              key=lambda r: r.fun)
    if "mu" in like.free and start is None and _flat(like, res.x, "mu"):
        # Ended on the plateau: the grid's best point can sit at an e far enough from the
        # best one that the line in mu misses the valley; a scan of the profile from the
        # end point re-optimises e at every mu.
        scanned = local_minimum(like, _profile_scan(like, res.x, "mu"), scale / FINE_SIMPLEX)
        res = min(res, scanned, key=lambda r: r.fun)
    return res


def search_scale(like):
    """The first simplex's size per free parameter: a twentieth of its search range."""
    return np.array([0.05 * (like.search[p][1] - like.search[p][0]) for p in like.free])
