"""The textbook fit of a drop-test table: the exact model, every input known, plain maximum
likelihood.

A check on the fit's intervals that shares none of its machinery: a table made by
:func:`mcbat.testing.drop_tables.drop_table` is fitted with its *true* impact parameters and
contact points (``table.attrs["truth"]``), so nothing is marginalised, drawn or estimated but
``e*`` and ``mu``: ``-ln L = sum chi^2 / 2`` over the rows' three observables with their
stated errors, minimised with scipy, and ``mu``'s profile-likelihood interval (``-ln L``
rises by 1/2 with ``e*`` re-optimised). If its intervals hold the truth less often than
68 %, the cause lies in the problem (the likelihood is not quadratic on the scale of its
errors), not in how :func:`mcbat.stats.fit.fit` marginalises the inputs.

:func:`mu_information_share` says how much of the Fisher information on ``mu`` the few
most informative rows carry: in the drop test it rests on the rows near the change from
sliding to rolling, where the observables turn steeply with ``mu``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from mcbat.testing.drop_tables import kernel_solver

__all__ = ["mu_information_share", "textbook_fit"]

OBSERVABLES = ("exit_speed", "scattering_angle", "spin_out")


def _arrays(table):
    truth = table.attrs["truth"]
    y = table[list(OBSERVABLES)].to_numpy(float)
    s = table[[f"{c}_err" for c in OBSERVABLES]].to_numpy(float)
    return (np.asarray(truth["impact_parameter"], float), table["spin_in"].to_numpy(float),
            np.asarray(truth["axial"], float), float(truth["e_x"]), y, s)


def textbook_fit(table, mu_range=(0.01, 1.0), e_range=(0.3, 0.95)):
    """Maximum likelihood of ``e*`` and ``mu`` with every input at its true value.

    Parameters
    ----------
    table : pandas.DataFrame
        A table of :func:`mcbat.testing.drop_tables.drop_table` (its ``attrs["truth"]``
        holds the true impact parameters, m, and contact points, m from the bat's CM).
    mu_range, e_range : (float, float)
        Where the maximum is searched.

    Returns
    -------
    dict
        ``mu``, ``e`` (the best fit), ``lower_error``, ``upper_error`` (``mu``'s 68 %
        profile-likelihood interval; ``inf`` on a side that stays below the rise of 1/2
        up to the end of ``mu_range``), ``neg_log_likelihood`` at the best fit and
        ``plateau_rise``, how far ``-ln L`` lies above it where every drop sticks (the end
        of ``mu_range``).
    """
    b, spin, axial, e_x, y, s = _arrays(table)

    def nll(e, mu):
        f = kernel_solver(b, spin, axial, e, mu, e_x)
        return 0.5 * float((((y - f) / s) ** 2).sum())

    def profile(mu):
        return optimize.minimize_scalar(lambda e: nll(e, mu), bounds=e_range,
                                        method="bounded", options={"xatol": 1e-7}).fun

    # Above the mu at which every drop sticks the likelihood is flat, and its maximum can
    # lie in a valley a few per cent wide just below that plateau: a fine grid finds it.
    grid = np.geomspace(*mu_range, 160)
    i = int(np.argmin([profile(m) for m in grid]))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    best = optimize.minimize_scalar(profile, bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-7})
    mu0, nll0 = float(best.x), float(best.fun)
    e0 = optimize.minimize_scalar(lambda e: nll(e, mu0), bounds=e_range, method="bounded",
                                  options={"xatol": 1e-7}).x

    def error(sign):
        """The distance to the rise of 1/2 on one side; inf if none within ``mu_range``."""
        def rise(d):
            return profile(mu0 + sign * d) - nll0 - 0.5
        room = (mu_range[1] - mu0) if sign > 0 else (mu0 - mu_range[0])
        step = min(1e-3, room)
        while rise(step) < 0:
            if step >= room:
                return math.inf
            step = min(2 * step, room)
        return optimize.brentq(rise, 0.0, step, xtol=1e-8)

    return {"mu": mu0, "e": float(e0), "lower_error": error(-1), "upper_error": error(1),
            "neg_log_likelihood": nll0, "plateau_rise": profile(mu_range[1]) - nll0}


def mu_information_share(table, rows=3, step=1e-4):
    """The share of the Fisher information on ``mu`` (at the truth, ``e*`` profiled out)
    that the ``rows`` most informative rows carry, and ``mu``'s Cramer-Rao error.

    Returns
    -------
    share : float
        Between ``rows / len(table)`` (the information spread evenly) and 1.
    error : float
        ``sqrt((F^-1)_mu,mu)``, the Fisher matrix ``F`` of ``(e*, mu)`` at the truth.
    """
    b, spin, axial, e_x, y, s = _arrays(table)
    truth = table.attrs["truth"]
    e, mu = float(truth["e"]), float(truth["mu"])

    def scaled(e_, mu_):
        return kernel_solver(b, spin, axial, e_, mu_, e_x) / s

    d_e = (scaled(e + step, mu) - scaled(e - step, mu)) / (2 * step)
    d_mu = (scaled(e, mu + step) - scaled(e, mu - step)) / (2 * step)
    jac = np.stack([d_e.ravel(), d_mu.ravel()], axis=1)
    fisher = jac.T @ jac
    # Each row's information on mu once e* is profiled out: its part of the Schur
    # complement F_mm - F_me^2 / F_ee.
    slope = fisher[0, 1] / fisher[0, 0]
    per_row = ((d_mu - slope * d_e) ** 2).sum(axis=1)
    top = np.sort(per_row)[::-1]
    return float(top[:rows].sum() / top.sum()), float(np.sqrt(np.linalg.inv(fisher)[1, 1]))
