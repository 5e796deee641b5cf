"""One-sided limits that hold the truth in 95 % of the tables that report one.

A fit reports a one-sided limit when its profile likelihood stays flat up to the end of a
parameter's range on one side (:mod:`mcbat.stats.intervals`). Whether it does is decided
by the data: at ``mu = 0.18`` a drop-test table is flat above only when its noise made the
few rows that slide look stuck, and the same noise moves the likelihood-ratio limit (a rise
of 1.353) towards the flat side. Among the tables that report a limit, that limit then
holds the truth far less often than 95 % when such tables are rare
(``validation/limit_selection.py``: 44 % where 1.3 % of the tables report one).

The limit here is conditional on that selection (selective inference: Fithian, Sun &
Taylor, arXiv:1410.2597): a value ``t`` is excluded when, among tables simulated at ``t``
whose profile is flat on the same side, fewer than 5 % rise at ``t`` by as much as the data
do. The simulated tables come from a normal surrogate of the model along the profile
(:func:`surrogate_rises`): the rises are fast to compute for 10^5 tables, so even a
selection that one table in a thousand passes is resolved.
"""

from __future__ import annotations

import math

import numpy as np

from mcbat.stats.likelihood import FREE

__all__ = ["MAX_TABLES", "MIN_SELECTED", "TABLES", "conditional_limit", "conditional_p_value",
           "flat_side_mask", "selective_limit", "surrogate", "surrogate_rises"]

TABLES = 20_000
"""Tables simulated at each value tried (more, up to :data:`MAX_TABLES`, when fewer than
:data:`MIN_SELECTED` of them are flat on the limit's free side)."""
MAX_TABLES = 320_000
"""The most tables simulated at one value."""
MIN_SELECTED = 400
"""Flat tables wanted at each value: the share among them that rise beyond the data's is
then known to about 1 % near 5 %."""


def surrogate_rises(curves, variance, y):
    """Rise of ``-ln L`` above its minimum over the grid, for each table.

    Parameters
    ----------
    curves : ndarray, (G, D)
        The model's prediction of the ``D`` measured values (rows times observables,
        flattened) at each of ``G`` grid values of the parameter.
    variance : ndarray, (D,)
        Their variances.
    y : ndarray, (N, D) or (D,)
        Tables of measured values.

    Returns
    -------
    ndarray, (N, G) or (G,)
    """
    y = np.asarray(y, float)
    # -2 ln L = sum (y - f)^2 / v: the y^2 term is the same at every grid value.
    quad = (curves ** 2 / variance).sum(axis=1) - 2.0 * (y / variance) @ curves.T
    return 0.5 * (quad - quad.min(axis=-1, keepdims=True))


def flat_side_mask(rises, sign, flat_rise):
    """Whether each table's profile stays below ``flat_rise`` from its minimum to the end
    of the grid on the side ``-sign`` (a lower limit, ``sign = -1``, is flat above)."""
    rises = np.atleast_2d(rises)
    g = rises.shape[1]
    best = rises.argmin(axis=1)[:, None]
    index = np.arange(g)[None, :]
    beyond = index >= best if sign < 0 else index <= best
    return np.where(beyond, rises, -np.inf).max(axis=1) < flat_rise


def conditional_p_value(curves, variance, rise, j, sign, rng, flat_rise):
    """Share of the tables simulated at grid value ``j`` whose profile is flat on the side
    ``-sign`` that rise at ``j`` by at least ``rise`` (the p-value of that value, conditional
    on the flat side).

    Parameters
    ----------
    curves, variance : ndarray
        The surrogate (:func:`surrogate_rises`).
    rise : float
        The data's rise of ``-ln L`` at grid value ``j``.
    j : int
        Index of the value tested.
    sign : {-1, 1}
        -1 for a lower limit (the profile is flat above).
    rng : numpy.random.Generator
        Draws the simulated tables: :data:`TABLES` first, doubled until
        :data:`MIN_SELECTED` are flat or :data:`MAX_TABLES` were drawn.
    flat_rise : float
        See :func:`flat_side_mask`.

    Returns
    -------
    float
        The p-value; 0 when fewer than a quarter of :data:`MIN_SELECTED` simulated tables
        are flat (a value under which hardly any table is flat on that side cannot have
        given flat data: excluded rather than judged on a handful of tables).
    """
    sd = np.sqrt(variance)
    selected = beyond = tables = 0
    n = TABLES
    while True:
        z = rng.standard_normal((n, curves.shape[1]))
        rises = surrogate_rises(curves, variance, curves[j] + sd * z)
        flat = flat_side_mask(rises, sign, flat_rise)
        selected += int(flat.sum())
        beyond += int((flat & (rises[:, j] >= rise)).sum())
        tables += n
        if selected >= MIN_SELECTED or tables >= MAX_TABLES:
            break
        n = min(2 * n, MAX_TABLES - tables)
    return beyond / selected if selected >= MIN_SELECTED // 4 else 0.0


def selective_limit(grid, curves, variance, y, sign, rng, flat_rise, level=0.95):
    """The one-sided limit at ``level``, conditional on the profile being flat on the other
    side (module docstring).

    Parameters
    ----------
    grid : ndarray, (G,)
        Values of the parameter, increasing, from beyond the limit to the end of its
        range on the flat side.
    curves, variance : ndarray
        The surrogate (:func:`surrogate_rises`).
    y : ndarray, (D,)
        The measured values.
    sign : {-1, 1}
        -1 for a lower limit (the profile is flat above), 1 for an upper limit.
    rng : numpy.random.Generator
        Draws the simulated tables.
    flat_rise : float
        A profile is flat on a side when its rise stays below this up to the grid's end
        (and a value whose rise is below it is never excluded).
    level : float
        Confidence level.

    Returns
    -------
    limit : float or None
        None when the surrogate's profile of the data is not flat on that side (the
        surrogate does not describe the fit's likelihood there); the grid's far end when no
        value of the grid is excluded.
    p_values : dict
        Grid value -> the conditional p-value found there (the values tried).
    """
    grid, curves = np.asarray(grid, float), np.asarray(curves, float)
    observed = surrogate_rises(curves, variance, y)
    if not flat_side_mask(observed, sign, flat_rise)[0]:
        return None, {}
    best = int(observed.argmin())
    order = range(best - 1, -1, -1) if sign < 0 else range(best + 1, len(grid))
    alpha = 1.0 - level
    p_values, last = {}, None
    for j in order:
        if observed[j] < flat_rise:  # within the 68 % interval: never excluded at 95 %
            continue
        p = conditional_p_value(curves, variance, observed[j], j, sign, rng, flat_rise)
        p_values[float(grid[j])] = p
        if p < alpha:
            if last is None:
                # Not interpolated towards the neighbour that was not tried: the p-value
                # falls steeply from the 68 % interval's end, and a log-linear guess from
                # p = 1 there places the limit beyond the one a finer grid finds (the
                # miniature model: 0.178-0.187 against 0.173). The grid value is
                # conservative.
                return float(grid[j]), p_values
            (t0, p0), t1 = last, float(grid[j])
            # log p is about linear in t between neighbouring values of the grid.
            if p <= 0.0:
                return t1, p_values
            w = (math.log(p0) - math.log(alpha)) / (math.log(p0) - math.log(p))
            return t0 + w * (t1 - t0), p_values
        last = (float(grid[j]), max(p, 1e-300))
    return float(grid[0] if sign < 0 else grid[-1]), p_values


GRID_BEYOND = 5.0
"""The grid reaches this many times the distance between the likelihood-ratio limit and
the 68 % interval's end beyond that limit (a rise of about 9 for a normal likelihood)."""
GRID_POINTS = (24, 10)
"""Grid values: evenly spaced over the bounded side, then denser near the flat side's
start, out to the end of the range."""


def surrogate(like, best, grid, point):
    """The normal surrogate of ``like`` along a parameter's profile.

    Each row's prediction at a grid value is the average of its draws at the profile's
    point there, weighted by the draws' posterior at the best fit (with the mixture
    likelihood: the measured inputs stay where the observables put them; with the normal
    form every good draw weighs the same); its variance is the measurement's plus that
    posterior's spread.

    Parameters
    ----------
    like : mcbat.stats.likelihood.Likelihood
    best : ndarray
        The best fit.
    grid : ndarray
        Values of the parameter.
    point : callable
        ``point(t)``: the profile's point (all free parameters) at value ``t``.

    Returns
    -------
    grid, curves, variance, y
        The grid values the model could evaluate, the predictions there (G, D), their
        variances and the measured values (D,), flattened over rows and observables.
    """
    log_w = like.posterior_log_weights(best)
    if log_w is None:
        return np.zeros(0), np.zeros((0, like.y.size)), like.s2.ravel(), like.y.ravel()
    sims, _ = like.last_draws
    keep, curves = [], []
    weights = np.exp(log_w - log_w.max(axis=1, keepdims=True))
    mean = np.einsum("rk,rko->ro", weights, sims) / weights.sum(axis=1)[:, None]
    spread = np.einsum("rk,rko->ro", weights, (sims - mean[:, None, :]) ** 2)
    variance = like.s2 + spread / weights.sum(axis=1)[:, None]
    for t in grid:
        pred = like.predict(point(t))
        if pred is None:
            continue
        sims_t, ok_t = like.last_draws
        w = np.where(ok_t, weights, 0.0)
        total = w.sum(axis=1)
        if not (total > 0).all():
            continue
        keep.append(t)
        curves.append((np.einsum("rk,rko->ro", w, sims_t) / total[:, None]).ravel())
    return np.array(keep), np.array(curves), variance.ravel(), like.y.ravel()


def conditional_limit(like, best, index, sign, point, lr_limit, root, edge, seed,
                      flat_rise, level=0.95):
    """The one-sided limit of free parameter ``index``, conditional on its profile being
    flat towards ``edge`` (module docstring); None when the surrogate does not see the
    profile flat (the caller keeps the likelihood-ratio limit ``lr_limit``).

    ``sign`` is -1 for a lower limit; ``root`` is where the profile's rise reaches 1/2 on
    the bounded side; ``point(t)`` the profile's point at ``t``.
    """
    lo, hi = FREE[like.free[index]]
    span = abs(root - lr_limit)
    far = min(max(lr_limit + sign * GRID_BEYOND * span, lo), hi)
    start = root - sign * 2.0 * span  # a little into the flat side
    bounded = np.linspace(far, start, GRID_POINTS[0])
    u = np.linspace(0.0, 1.0, GRID_POINTS[1] + 1)[1:]
    flat = start + (edge - start) * u ** 2
    grid = np.concatenate([bounded, flat])
    grid = np.sort(grid)
    grid, curves, variance, y = surrogate(like, best, grid, point)
    if len(grid) < 4:
        return None
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 17, index)))
    limit, _ = selective_limit(grid, curves, variance, y, sign, rng, flat_rise, level)
    return limit
