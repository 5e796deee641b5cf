"""The textbook fit of a drop-test table: the exact model, every input known, plain maximum
likelihood.

A check on the fit's intervals that shares none of its machinery: a table made by
``harness.drop_tables.drop_table`` is fitted with its *true* impact parameters and
contact points (``table.attrs["truth"]``), so nothing is marginalised, drawn or estimated but
``e*`` and ``mu``: ``-ln L = sum chi^2 / 2`` over the rows' three observables with their
stated errors, minimised with scipy, and ``mu``'s profile-likelihood interval (``-ln L``
rises by 1/2 with ``e*`` re-optimised). If its intervals hold the truth less often than
68 %, the cause lies in the problem (the likelihood is not quadratic on the scale of its
errors), not in how ``mcbat.stats.fit.estimate.fit`` marginalises the inputs.

``mu_information_share`` says how much of the Fisher information on ``mu`` the few
most informative rows carry: in the drop test it rests on the rows near the change from
sliding to rolling, where the observables turn steeply with ``mu``.

``marginal_fit`` is the textbook fit of a table whose impact parameters are known only
as measured: each row's likelihood integrated over its true impact parameter by quadrature
(the true distribution of the table's impact parameters as the prior), and, with
``contact_nodes``, over its contact point too (``mcbat.stats.fit.estimate.fit`` does not know
the contact points either): the exact marginal likelihood that ``mcbat.stats.fit.estimate.fit``
estimates with draws.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize
from scipy.special import roots_legendre

from harness.drop_tables import DROP_TEST, kernel_solver

__all__ = ["marginal_fit", "marginal_neg_log_likelihood", "mu_information_share",
           "textbook_fit"]

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
        A table of ``harness.drop_tables.drop_table`` (its ``attrs["truth"]``
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


def marginal_neg_log_likelihood(table, prior_range=(-0.0254, 0.0254), nodes=128, reach=6.0,
                                contact_nodes=0):
    """Each row's exact ``-ln L_i(e*, mu)`` with its true impact parameter integrated out (up
    to a constant that depends on neither): its prior uniform over ``prior_range`` (m; the
    drop tables' default draw), times the normal of its measurement, integrated by
    Gauss-Legendre quadrature with ``nodes`` nodes over the prior's range within ``reach``
    errors of the measured value.

    Parameters
    ----------
    table : pandas.DataFrame
        A table of ``harness.drop_tables.drop_table`` with an
        ``impact_parameter_err`` column, its true impact parameters drawn uniformly over
        ``prior_range`` (not at the ``edges``).
    contact_nodes : int
        0: each row's contact point at its true value (``attrs["truth"]["axial"]``); else
        integrated over its true distribution, uniform over the drop test's contact range
        (``harness.drop_tables.DROP_TEST``), by Gauss-Legendre quadrature with
        this many nodes, as a fit that does not know the contact points must.

    Returns
    -------
    callable
        ``nll(e, mu)`` -> ndarray (rows,).
    """
    obs = list(OBSERVABLES)
    y = table[obs].to_numpy(float)
    s = table[[f"{c}_err" for c in obs]].to_numpy(float)
    measured = table["impact_parameter"].to_numpy(float)
    sigma = table["impact_parameter_err"].to_numpy(float)
    rows = len(table)
    x, w = roots_legendre(nodes)
    lo = np.maximum(prior_range[0], measured - reach * sigma)
    hi = np.minimum(prior_range[1], measured + reach * sigma)
    b = 0.5 * (lo + hi)[:, None] + 0.5 * (hi - lo)[:, None] * x[None, :]
    # log of the quadrature weight times the measurement's density (the uniform prior's
    # constant and the normal's own do not depend on e* or mu).
    log_weight = (np.log(0.5 * (hi - lo))[:, None] + np.log(w)[None, :]
                  - 0.5 * ((b - measured[:, None]) / sigma[:, None]) ** 2)
    if contact_nodes:
        xa, wa = roots_legendre(contact_nodes)
        near, far = DROP_TEST["from_barrel_end"]
        centre, half = DROP_TEST["cm_from_barrel_end"] - 0.5 * (near + far), 0.5 * (far - near)
        axial = np.broadcast_to(centre + half * xa, (rows, nodes, contact_nodes))
        b = np.repeat(b[:, :, None], contact_nodes, axis=2)
        log_weight = log_weight[:, :, None] + np.log(0.5 * wa)[None, None, :]
    else:
        axial = np.repeat(np.asarray(table.attrs["truth"]["axial"], float)[:, None], nodes,
                          axis=1)
    b, axial, log_weight = (a.reshape(rows, -1) for a in (b, axial, log_weight))
    points = b.shape[1]
    spin = np.repeat(table["spin_in"].to_numpy(float), points)
    y_nodes, s_nodes = np.repeat(y, points, axis=0), np.repeat(s, points, axis=0)
    e_x = float(table.attrs["truth"]["e_x"])

    def nll(e, mu):
        f = kernel_solver(b.ravel(), spin, axial.ravel(), e, mu, e_x)
        log_l = (-0.5 * (((y_nodes - f) / s_nodes) ** 2).sum(axis=1)).reshape(rows, points)
        log_l += log_weight
        top = log_l.max(axis=1)
        return -(top + np.log(np.exp(log_l - top[:, None]).sum(axis=1)))

    return nll


def marginal_fit(table, prior_range=(-0.0254, 0.0254), nodes=128, start=None, reach=6.0,
                 contact_nodes=0):
    """Maximum likelihood of ``e*`` and ``mu`` with each row's true impact parameter (and,
    with ``contact_nodes``, its contact point) integrated out exactly
    (``marginal_neg_log_likelihood``, whose parameters these are).

    Parameters
    ----------
    start : (float, float), optional
        ``(e*, mu)`` to start from (default: the textbook fit's).

    Returns
    -------
    dict
        ``e``, ``mu`` (the best fit), ``neg_log_likelihood`` there and ``evaluations``.
    """
    rows_nll = marginal_neg_log_likelihood(table, prior_range, nodes, reach, contact_nodes)

    def nll(theta):
        e, mu = theta
        if not (0.05 < e < 0.99 and 1e-3 < mu < 2.0):
            return 1e30
        return float(rows_nll(e, mu).sum())

    if start is None:
        tb = textbook_fit(table)
        start = (tb["e"], tb["mu"])
    start = np.asarray(start, float)
    # A simplex a few errors of a 3000-row table wide: the minimum lies within a few
    # errors of the textbook fit's, and the tolerance is a hundredth of those errors.
    simplex = [start, start + [4e-4, 0.0], start + [0.0, 4e-4]]
    best = optimize.minimize(nll, start, method="Nelder-Mead",
                             options={"xatol": 2e-7, "fatol": 1e-4,
                                      "initial_simplex": simplex})
    return {"e": float(best.x[0]), "mu": float(best.x[1]),
            "neg_log_likelihood": float(best.fun), "evaluations": int(best.nfev)}
