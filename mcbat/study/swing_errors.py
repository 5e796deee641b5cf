"""The true swing given the measured one: the draws behind ``[pitches.swing_error]``.

A measured swing key ``x`` (Statcast's bat speed, attack angle, attack direction) carries
a Gaussian error of sd ``s`` (classical: the measured value is the true one plus the
error). Each sample's true value is drawn given its row's measured one
(:func:`true_values`), with the selected rows as the population: for the plain error a
normal population of the rows' mean ``m`` and variance ``v``, ``true = m + k (x - m) +
sqrt(k) s z``, ``k = max(0, 1 - s^2 / v)``. With ``[pitches.swing_error.bat_speed_outliers]``
a share of the bat speeds reads far too fast, and the population is the rows' own bat
speeds, deconvolved (:func:`outlier_population`, :func:`outlier_posterior_draw`). The
random numbers are the study's (``mcbat.study.game``); this module is numpy only.
"""

from __future__ import annotations

import math
from types import MappingProxyType

import numpy as np

from mcbat.checks import check_keys
from mcbat.errors import InputError
from mcbat.study.distributions import fixed_value, parse

__all__ = ["DECONVOLUTION_STEPS", "OUTLIERS", "clip_true", "outlier_population",
           "outlier_posterior_draw", "parse_swing_errors", "swing_table", "true_values"]

OUTLIERS = "bat_speed_outliers"
"""The sub-table of ``[pitches.swing_error]`` of the bat speeds measured far too fast."""

DECONVOLUTION_STEPS = 30
"""Expectation-maximisation steps of :func:`outlier_population`."""


def parse_swing_errors(table, swing, quantities) -> tuple:
    """``[pitches]``'s ``[pitches.swing_error]`` -> (drawn swing key -> the sd of its
    measurement error, SI; the outliers' ``(fraction, excess m/s, spread m/s)`` or None).
    ``quantities``: each swing key's physical quantity (``"bat_speed"`` -> speed)."""
    errors = swing_table(table, "swing_error", swing, (*quantities, OUTLIERS),
                         "the errors of the measured swings drawn from the rows")
    out = {}
    for key, spec in errors.items():
        if key == OUTLIERS:
            continue
        name = f"pitches.swing_error.{key}"
        dist = parse(spec, name, quantities[key])
        if dist.family != "fixed" or not (math.isfinite(dist.value) and dist.value >= 0.0):
            raise InputError(name, f"must be a fixed value >= 0 (the sd of the measurement "
                             f"error, e.g. {{ value = 4, unit = \"deg\" }}), got {spec!r}")
        out[f"swing.{key}"] = float(dist.value)
    return MappingProxyType(out), _parse_outliers(errors, out, quantities["bat_speed"])


def swing_table(table, key, swing, allowed, what) -> dict:
    """``[pitches]``'s sub-table ``key`` (``{}`` when absent), checked: a table, only with
    ``swing = true`` (``what`` says what it holds), its keys among ``allowed``."""
    name = f"pitches.{key}"
    sub = table.get(key, {})
    if not isinstance(sub, dict):
        raise InputError(name, f"must be a table ([{name}]), got {sub!r}")
    if sub and not swing:
        raise InputError(name, f"only with pitches.swing = true ({what})")
    check_keys(sub, name, (), allowed)
    return sub


def _parse_outliers(errors, sds, quantity):
    """``[pitches.swing_error.bat_speed_outliers]`` -> ``(fraction, excess m/s, spread
    m/s)``, or None without it. It needs ``bat_speed`` in ``[pitches.swing_error]``: the
    other rows' error, and ``spread``'s default."""
    table = errors.get(OUTLIERS)
    if table is None:
        return None
    name = f"pitches.swing_error.{OUTLIERS}"
    check_keys(table, name, ("fraction", "excess"), ("spread",))
    if "swing.bat_speed" not in sds:
        raise InputError(name, "needs pitches.swing_error.bat_speed (the error of the "
                         "other measured bat speeds)")
    fraction = table["fraction"]
    if (isinstance(fraction, bool) or not isinstance(fraction, (int, float))
            or not 0.0 <= fraction < 0.5):
        raise InputError(f"{name}.fraction", f"must be a number in [0, 0.5) (the share of "
                         f"measured bat speeds that are outliers), got {fraction!r}")
    values = {}
    for key in ("excess", "spread"):
        if key not in table:
            continue
        values[key] = fixed_value(table[key], f"{name}.{key}", quantity,
                                  '{ value = 12, unit = "mph" }')
    spread = values.get("spread", sds["swing.bat_speed"])
    if not spread >= 0.0:
        raise InputError(f"{name}.spread", f"must be >= 0, got {table['spread']!r}")
    return float(fraction), values["excess"], spread


def true_values(measured, rows, sd, z, outliers=None, u_pick=None, population=None):
    """Draws of the true values (SI) of the samples' ``measured`` ones: the plain error's
    (``z`` standard normals), or with ``outliers = (f, excess, spread)`` and ``f > 0`` the
    two-part error's (``u_pick`` uniforms; ``population`` from :func:`outlier_population`
    of ``rows``, the selected rows' finite measured values)."""
    if outliers and outliers[0] > 0.0:
        return outlier_posterior_draw(measured, sd, outliers, u_pick, population)
    m = float(rows.mean()) if rows.size else 0.0
    v = float(rows.var()) if rows.size > 1 else 0.0
    k = max(0.0, 1.0 - sd * sd / v) if v > 0.0 else 0.0
    return m + k * (measured - m) + math.sqrt(k) * sd * z


def clip_true(key, true, vertical_support=None) -> np.ndarray:
    """Hold drawn true values inside the study's ranges: a bat speed at or above 0, an
    attack angle within what the steepest vertical bat angle allows (``vertical_support``:
    its distribution's support, rad), an angle within ±90°."""
    if key == "swing.bat_speed":
        return np.maximum(true, 0.0)
    if key == "swing.attack_angle":
        limit = 0.5 * math.pi - 1e-6
        if vertical_support is not None:
            largest = max(abs(vertical_support[0]), abs(vertical_support[1]))
            if largest > 0.0:
                limit = min(limit, math.atan((1.0 - 1e-6) / math.tan(largest)))
        return np.clip(true, -limit, limit)
    return np.clip(true, -0.5 * math.pi + 1e-6, 0.5 * math.pi - 1e-6)


def outlier_population(population, sd, outliers, block=4096) -> tuple:
    """The grid of true bat speeds (m/s) and the population's weights on it that
    :func:`outlier_posterior_draw` draws with: the population whose measurements, with the
    two-part error of ``outliers = (f, excess, spread)`` and ``sd``, give the selected
    rows' own (``population``), deconvolved by expectation-maximisation (each row's
    posterior over the grid, summed; ``DECONVOLUTION_STEPS`` steps), so that the outliers'
    own readings do not count as fast true swings. A file's bat speeds are skewed (a long
    tail of slow swings, few fast ones): whether a fast reading is an outlier depends on
    how rare such swings are in the file itself, not in a normal law of its mean and
    variance. Steps of the grid: ``sd / 10``; the rows are counted at their nearest grid
    point."""
    f, excess, spread = outliers
    width = max(sd, spread, 1e-3)
    step = width / 10.0
    low = float(population.min()) - max(excess, 0.0) - 6.0 * width
    high = float(population.max()) + max(-excess, 0.0) + 6.0 * width
    grid = low + step * np.arange(int(np.ceil((high - low) / step)) + 1)
    # (the rows counted on the grid: the cost does not grow with the rows, and a step of
    # sd / 10 moves no reading by more than a twentieth of its error)
    where = np.clip(np.rint((np.asarray(population, float) - low) / step).astype(np.int64),
                    0, grid.size - 1)
    counts = np.bincount(where, minlength=grid.size).astype(float)
    seen, counts = grid[counts > 0], counts[counts > 0]
    prior = np.full(grid.size, 1.0 / grid.size)
    for _ in range(DECONVOLUTION_STEPS):
        updated = np.zeros(grid.size)
        for start in range(0, seen.size, block):
            weights = prior[None, :] * _two_part(seen[start:start + block], grid, sd,
                                                 outliers)
            weights /= weights.sum(axis=1, keepdims=True)
            updated += counts[start:start + block] @ weights
        prior = updated / updated.sum() + 1e-300
    return grid, prior


def outlier_posterior_draw(measured, sd, outliers, u_pick, population,
                           block=4096) -> np.ndarray:
    """Draws of the true bat speeds given the ``measured`` ones (m/s) when a share of the
    measurements read far too fast (``[pitches.swing_error.bat_speed_outliers]``).

    The measured value is the true one plus an error that is ``N(0, sd)`` for a share
    ``1 - f`` of the rows and ``N(excess, spread)`` for the share ``f`` (``outliers = (f,
    excess, spread)``); ``population = (grid, weights)`` of :func:`outlier_population`.
    The posterior on the grid is drawn by its inverse distribution function at ``u_pick``
    (uniform), linear within a step."""
    grid, prior = population
    step = grid[1] - grid[0]
    values, where = np.unique(np.asarray(measured, float), return_inverse=True)
    out = np.empty(where.size)
    for start in range(0, values.size, block):
        cdf = np.cumsum(prior[None, :] * _two_part(values[start:start + block], grid, sd,
                                                   outliers), axis=1)
        cdf /= cdf[:, -1:]
        mine = np.flatnonzero((where >= start) & (where < start + block))
        rows, u = cdf[where[mine] - start], np.asarray(u_pick, float)[mine]
        k = np.minimum((rows < u[:, None]).sum(axis=1), grid.size - 1)
        below = np.where(k > 0, rows[np.arange(k.size), k - 1], 0.0)
        at = rows[np.arange(k.size), k]
        share = np.clip((u - below) / np.maximum(at - below, 1e-300), 0.0, 1.0)
        out[mine] = grid[k] - step * (1.0 - share)
    return out


def _two_part(values, grid, sd, outliers) -> np.ndarray:
    """The likelihood of measured ``values`` (rows) at the true speeds of ``grid``
    (columns) under the two-part error."""
    f, excess, spread = outliers
    step = grid[1] - grid[0]
    x = values[:, None] - grid[None, :]
    return (1.0 - f) * _normal(x, 0.0, sd, step) + f * _normal(x, excess, spread, step)


def _normal(x, mean, sd, step) -> np.ndarray:
    """The normal density of ``x`` (unnormalised: the grid's weights), a point mass on the
    grid for ``sd`` below its step."""
    sd = max(sd, step)
    return np.exp(-0.5 * ((x - mean) / sd) ** 2) / sd


