"""A simulated dataset against a measured table: two-sample statistics per shared column
and in the launch speed / launch angle plane (``mcbat compare``, ``docs/compare.md``).

The statistics, on plain arrays:

* :func:`ks_test`: the two-sample Kolmogorov-Smirnov distance ``D = max |F - G|`` of the
  two empirical distribution functions, with scipy's p-value (``scipy.stats.ks_2samp``,
  ``method="auto"``: the exact distribution for small samples, the asymptotic one
  otherwise). It assumes continuous data; rounded values (Statcast's launch angles are
  whole degrees) make it conservative.
* :func:`wasserstein`: the 1-D Wasserstein (earth mover's) distance ``∫ |F - G| dx``, in the
  column's unit: how far, on average, the measured distribution must be moved to become the
  simulated one.
* :func:`energy_test`: the energy distance ``sqrt(2 E|X-Y| - E|X-X'| - E|Y-Y'|)``
  (Székely and Rizzo; ``scipy.stats.energy_distance``'s definition, in the column's unit)
  with a permutation p-value.
* :func:`plane_energy_test`: the energy distance of two samples of points in the plane,
  on coordinates standardized by the pooled sample's standard deviations (so that mph and
  degrees weigh alike, and the scaling is the same under every permutation), with a
  permutation p-value.

Permutation p-values are ``(1 + k) / (1 + P)``, ``k`` the number of the ``P`` random
relabellings of the pooled sample whose statistic reaches the observed one: valid at any
sample size, never 0, with a resolution of ``1 / (1 + P)``.

:func:`compare` runs them on two DataFrames (rows with NaN dropped per column and counted;
units checked and converted), :func:`read_simulated` and :func:`read_measured` read the
inputs, :func:`fig_compare` draws the figure.
"""

from __future__ import annotations

import json
import math
import os
import warnings
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mcbat.errors import InputError

__all__ = ["MAX_ROWS", "PERMUTATIONS", "PLANE", "PLANE_ROWS", "UNIT_FACTORS", "Comparison",
           "check_settings", "compare", "convert", "energy_test", "fig_compare", "ks_test",
           "plane_energy_test", "read_measured", "read_simulated", "wasserstein"]

PERMUTATIONS = 1000
"""Default number of random relabellings of a permutation test (p-value resolution 1/1001)."""
MAX_ROWS = 20_000
"""Each side of a column's energy test is subsampled (seeded, without replacement) to at
most this many rows; the KS statistic and the Wasserstein distance use every row."""
PLANE_ROWS = 2_000
"""Each side of the plane's energy test is subsampled to at most this many rows: the test
holds the pooled sample's distance matrix (4,000 x 4,000 at most, 128 MB)."""
PLANE = ("launch_speed", "launch_angle")
"""The plane compared in two dimensions when both sides have both columns."""

UNIT_FACTORS = {
    # unit: (quantity, factor to SI)
    "mph": ("speed", 0.44704), "m/s": ("speed", 1.0), "km/h": ("speed", 1.0 / 3.6),
    "ft/s": ("speed", 0.3048),
    "deg": ("angle", math.pi / 180.0), "rad": ("angle", 1.0),
    "rpm": ("spin", 2.0 * math.pi / 60.0), "rad/s": ("spin", 1.0),
    "ft": ("length", 0.3048), "m": ("length", 1.0), "in": ("length", 0.0254),
    "cm": ("length", 0.01), "mm": ("length", 0.001),
    "s": ("time", 1.0),
    "kg": ("mass", 1.0), "g": ("mass", 0.001), "oz": ("mass", 0.028349523125),
    "J": ("energy", 1.0), "kg m/s": ("momentum", 1.0), "kg m^2": ("inertia", 1.0),
    "1": ("ratio", 1.0),
}
"""The units :func:`compare` knows, and converts between within one quantity. A column whose
unit is not here (codes, identifiers) is not compared."""

UNIT_SUSPICION = 1.5
"""A column whose unit the measured table does not state is read in the simulated column's
unit; it is refused when the measured values' median magnitude differs from the simulated
one by more than this factor *and* lies within :data:`UNIT_MATCH` of the factor between that
unit and another of its quantity (launch speeds in m/s: 0.447 of mph)."""
UNIT_MATCH = 1.3
"""See :data:`UNIT_SUSPICION`."""

_STATCAST_NAMES = {
    # the tidy Statcast table's name: the dataset's name of the same quantity
    "spin_rate": "pitch_spin_rate",  # the pitch's release spin: the dataset's spin_rate is
                                     # the batted ball's
    "vertical_approach_angle": "pitch_vertical_approach_angle",
    "horizontal_approach_angle": "pitch_horizontal_approach_angle",
    "hit_distance_sc": "hit_distance",
}
_STATCAST_COLUMNS = ("launch_speed", "launch_angle", "spray_angle", "hit_distance_sc",
                     "pitch_speed", "spin_rate", "vertical_approach_angle",
                     "horizontal_approach_angle", "bat_speed", "attack_angle",
                     "attack_direction")
"""The tidy table's columns that are quantities a game dataset also has (the same
definitions and sign conventions: docs/statcast.md, docs/batting.md)."""
_NOT_COMPARED = ("sample_id", "chunk")


# --------------------------------------------------------------------------------------
# the statistics, on arrays


def ks_test(x, y):
    """Two-sample Kolmogorov-Smirnov distance and p-value (``scipy.stats.ks_2samp``).

    Returns
    -------
    dict
        ``statistic`` (``max |F - G|``), ``p_value``, ``method`` (``"exact"`` or
        ``"asymptotic"``: scipy's choice for these sizes).
    """
    from scipy import stats

    x, y = _finite(x, "x"), _finite(y, "y")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = stats.ks_2samp(x, y, method="auto")
    # scipy's "auto" uses the exact distribution up to 10,000 rows on the larger side, and
    # falls back to the asymptotic one (with a warning) where the exact sum fails
    method = "exact" if max(len(x), len(y)) <= 10_000 else "asymptotic"
    if any("asymp" in str(w.message) for w in caught):
        method = "asymptotic"
    return {"statistic": float(result.statistic), "p_value": float(result.pvalue),
            "method": method}


def wasserstein(x, y):
    """The 1-D Wasserstein distance ``∫ |F - G| dx`` (in the values' unit)."""
    from scipy import stats

    return float(stats.wasserstein_distance(_finite(x, "x"), _finite(y, "y")))


def energy_test(x, y, permutations=PERMUTATIONS, seed=0):
    """Energy distance of two 1-D samples and its permutation p-value.

    The distance is ``sqrt(2 E|X-Y| - E|X-X'| - E|Y-Y'|) = sqrt(2 ∫ (F - G)^2 dx)`` over the
    empirical distributions (``scipy.stats.energy_distance``'s definition), in the values'
    unit. Each relabelling of the pooled sample is evaluated on the sorted pooled values
    (cumulative counts of each label): ``O(n + m)`` per permutation.

    Parameters
    ----------
    x, y : array_like
        Finite values (at least one each).
    permutations : int
        Random relabellings (0: no p-value).
    seed : int or sequence of int
        Seed of ``numpy.random.default_rng``: the same seed gives the same p-value.

    Returns
    -------
    dict
        ``distance``, ``p_value`` (None without permutations), ``permutations``.
    """
    x, y = _finite(x, "x"), _finite(y, "y")
    pooled = np.concatenate([x, y])
    order = np.argsort(pooled, kind="stable")
    dz = np.diff(pooled[order])
    labels = np.zeros(pooled.size, dtype=bool)
    labels[:x.size] = True
    labels = labels[order]
    observed = _energy_sq_sorted(dz, labels[None, :], x.size, y.size)[0]
    p_value = _permutation_p(observed, labels, permutations, seed,
                             lambda batch: _energy_sq_sorted(dz, batch, x.size, y.size))
    return {"distance": math.sqrt(max(observed, 0.0)), "p_value": p_value,
            "permutations": int(permutations)}


def _energy_sq_sorted(dz, labels, n_x, n_y):
    """``2 ∫ (F - G)^2`` for each row of ``labels`` (bool, the pooled values' sorted
    order; True for ``x``), ``dz`` the gaps between the sorted pooled values."""
    below_x = np.cumsum(labels[:, :-1], axis=1, dtype=np.int64)
    below = np.arange(1, labels.shape[1], dtype=np.int64)
    gap = below_x / n_x - (below - below_x) / n_y
    return 2.0 * (gap * gap) @ dz


def plane_energy_test(x, y, permutations=PERMUTATIONS, seed=0):
    """Energy distance of two samples of points in the plane (or any dimension), on
    coordinates standardized by the pooled sample, and its permutation p-value.

    Each coordinate is divided by its standard deviation over the pooled sample, which is
    the same under every relabelling; the distance is then
    ``sqrt(2 E|X-Y| - E|X-X'| - E|Y-Y'|)`` with Euclidean ``|.|`` (dimensionless). The
    pooled sample's distance matrix is computed once, and each relabelling's within- and
    between-sample sums come from one matrix product with the label vectors, so the
    memory is ``8 (n + m)^2`` bytes: subsample large samples first (:data:`PLANE_ROWS`).

    Parameters
    ----------
    x, y : array_like, shape (n, d) and (m, d)
        Finite points.
    permutations, seed
        As :func:`energy_test`.

    Returns
    -------
    dict
        ``distance``, ``p_value`` (None without permutations), ``permutations``, ``scale``
        (the pooled standard deviation of each coordinate).
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.ndim != 2 or y.ndim != 2 or x.shape[1] != y.shape[1]:
        raise InputError("x", "expected two arrays of points of one dimension, shapes "
                         f"(n, d) and (m, d); got {x.shape} and {y.shape}")
    if len(x) == 0 or len(y) == 0 or not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise InputError("x", "expected finite points, at least one on each side")
    pooled = np.concatenate([x, y])
    scale = pooled.std(axis=0)
    scale[scale == 0] = 1.0
    z = pooled / scale
    n_x, n_y = len(x), len(y)
    distances = np.empty((len(z), len(z)))
    for start in range(0, len(z), 512):  # in blocks: no (N, N, d) temporary
        block = z[start:start + 512]
        distances[start:start + 512] = np.sqrt(
            ((block[:, None, :] - z[None, :, :]) ** 2).sum(axis=2))
    row_sums = distances.sum(axis=1)
    total = row_sums.sum()

    def statistic(labels):  # labels: (B, N) bool, True for x
        weights = labels.astype(float)
        within_x = np.einsum("bi,bi->b", weights @ distances, weights)
        between = weights @ row_sums - within_x
        within_y = total - 2.0 * between - within_x
        return 2.0 * between / (n_x * n_y) - within_x / n_x**2 - within_y / n_y**2

    labels = np.zeros(len(z), dtype=bool)
    labels[:n_x] = True
    observed = statistic(labels[None, :])[0]
    p_value = _permutation_p(observed, labels, permutations, seed, statistic, batch=64)
    return {"distance": math.sqrt(max(observed, 0.0)), "p_value": p_value,
            "permutations": int(permutations), "scale": [float(s) for s in scale]}


def _permutation_p(observed, labels, permutations, seed, statistic, batch=256):
    """``(1 + k) / (1 + P)``: ``k`` of ``P`` random relabellings reach ``observed``."""
    if permutations < 0:
        raise InputError("permutations", f"must be an integer >= 0, got {permutations}")
    if permutations == 0:
        return None
    rng = np.random.default_rng(seed)
    # a relabelling that reproduces the observed one must count: allow for the rounding of
    # sums taken in another order
    threshold = observed - 1e-12 * abs(observed)
    reached = 0
    for start in range(0, permutations, batch):
        count = min(batch, permutations - start)
        shuffled = rng.permuted(np.broadcast_to(labels, (count, labels.size)), axis=1)
        reached += int((statistic(shuffled) >= threshold).sum())
    return (1.0 + reached) / (1.0 + permutations)


def _finite(values, name):
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0 or not np.isfinite(values).all():
        raise InputError(name, "expected finite values, at least one")
    return values


# --------------------------------------------------------------------------------------
# units


def convert(values, unit, to):
    """``values`` in ``unit`` expressed in ``to`` (both in :data:`UNIT_FACTORS`, of one
    quantity)."""
    if unit == to:
        return np.asarray(values, dtype=float)
    (kind, factor), (kind_to, factor_to) = UNIT_FACTORS[unit], UNIT_FACTORS[to]
    if kind != kind_to:
        raise InputError(None, f"cannot convert {unit} ({kind}) to {to} ({kind_to})")
    return np.asarray(values, dtype=float) * (factor / factor_to)


def _unit_suspicion(column, simulated, measured, unit):
    """A message when ``measured`` (whose table states no unit, read in ``unit``) looks like
    another unit of the same quantity, else None (:data:`UNIT_SUSPICION`)."""
    kind = UNIT_FACTORS[unit][0]
    if kind in ("ratio",):
        return None
    typical_sim = float(np.median(np.abs(simulated)))
    typical_meas = float(np.median(np.abs(measured)))
    if typical_sim <= 0 or typical_meas <= 0:
        return None
    ratio = typical_meas / typical_sim
    if abs(math.log(ratio)) <= math.log(UNIT_SUSPICION):
        return None
    for other, (other_kind, factor) in UNIT_FACTORS.items():
        if other_kind != kind or other == unit:
            continue
        expected = UNIT_FACTORS[unit][1] / factor  # a value in `other` read as `unit`
        if abs(math.log(ratio / expected)) < math.log(UNIT_MATCH):
            return (f"the measured values' median magnitude ({typical_meas:.4g}) is "
                    f"{ratio:.3g} times the simulated one ({typical_sim:.4g} {unit}), close "
                    f"to the {expected:.3g} of a value in {other}: wrong unit? The table "
                    f"states no unit for {column}, so it is read in {unit}; state its unit "
                    f"(units={{'{column}': '{other}'}}) to compare it converted, or "
                    f"(units={{'{column}': '{unit}'}}) to compare it as it is")
    return None


# --------------------------------------------------------------------------------------
# two tables


@dataclass
class Comparison:
    """What :func:`compare` found: ``columns`` (one dict per compared column), ``plane``
    (the launch speed / launch angle test, or None), ``not_compared`` (shared columns left
    out, with the reason), the settings and the two sides' descriptions."""

    columns: list
    plane: dict | None
    not_compared: list
    settings: dict
    simulated: dict = field(default_factory=dict)
    measured: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """JSON-ready (every number finite or None)."""
        return {"simulated": self.simulated, "measured": self.measured,
                "settings": self.settings, "columns": self.columns, "plane": self.plane,
                "not_compared": self.not_compared}

    def lines(self) -> list:
        """The table ``mcbat compare`` prints."""
        s = self.settings
        out = [f"{'column':<32} {'unit':<6} {'n sim':>8} {'n meas':>7} {'median sim':>11} "
               f"{'median meas':>11} {'KS D':>6} {'KS p':>8} {'Wasserst.':>10} "
               f"{'energy':>9} {'perm p':>7}"]
        for c in self.columns:
            sim, meas = c["simulated"], c["measured"]
            out.append(
                f"{c['column']:<32} {c['unit']:<6} {sim['rows']:>8,} {meas['rows']:>7,} "
                f"{sim['median']:>11.4g} {meas['median']:>11.4g} {c['ks']['statistic']:>6.3f} "
                f"{_p_text(c['ks']['p_value'], None):>8} {c['wasserstein']:>10.4g} "
                f"{c['energy']['distance']:>9.4g} "
                f"{_p_text(c['energy']['p_value'], s['p_value_resolution']):>7}")
        if self.plane is not None:
            p = self.plane
            out.append(f"plane {' x '.join(p['columns'])}: energy distance "
                       f"{p['distance']:.4f} (coordinates / pooled sd "
                       f"{p['scale'][0]:.3g} {p['units'][0]}, {p['scale'][1]:.3g} "
                       f"{p['units'][1]}), permutation p "
                       f"{_p_text(p['p_value'], s['p_value_resolution'])}; "
                       f"{p['simulated_rows']:,} simulated and {p['measured_rows']:,} "
                       "measured rows")
        dropped = [f"{c['column']} {c['simulated']['dropped']:,} sim / "
                   f"{c['measured']['dropped']:,} meas" for c in self.columns
                   if c["simulated"]["dropped"] or c["measured"]["dropped"]]
        if dropped:
            out.append("rows without a value (dropped per column): " + ", ".join(dropped))
        converted = [f"{c['column']} from {c['converted_from']}" for c in self.columns
                     if c["converted_from"]]
        if converted:
            out.append("converted to the unit shown: " + ", ".join(converted))
        out.append(f"p-values: KS from scipy (exact or asymptotic); energy from "
                   f"{s['permutations']:,} permutations (seed {s['seed']}), resolution "
                   f"{s['p_value_resolution']:.2g}; energy tests on at most "
                   f"{s['max_rows']:,} rows a side (plane: {s['plane_rows']:,}), "
                   "subsampled with the seed")
        capped = [c["column"] for c in self.columns if c["energy"]["subsampled"]]
        if capped:
            out.append("subsampled for the energy test: " + ", ".join(capped))
        for item in self.not_compared:
            out.append(f"not compared: {item['column']}: {item['reason']}")
        return out


def _shown_range(a, b):
    """From the lower to the upper 0.5 % quantile of whichever side reaches further."""
    low = min(np.quantile(a, 0.005), np.quantile(b, 0.005))
    high = max(np.quantile(a, 0.995), np.quantile(b, 0.995))
    return (low, high) if high > low else (low - 0.5, high + 0.5)


def _p_text(p, resolution):
    if p is None:
        return "-"
    if resolution is not None and p <= resolution * (1 + 1e-9):
        return f"<={p:.2g}"
    return f"{p:.3g}" if p >= 1e-3 else f"{p:.1e}"


def compare(simulated, measured, columns=None, *, units=None, permutations=PERMUTATIONS,
            seed=0, max_rows=MAX_ROWS, plane_rows=PLANE_ROWS, plane=PLANE):
    """Two-sample statistics of ``simulated`` against ``measured`` on their shared columns.

    Parameters
    ----------
    simulated : pandas.DataFrame
        A dataset (:func:`mcbat.load`), its units in ``attrs["units"]``.
    measured : pandas.DataFrame
        The measured rows; the units it states in ``attrs["units"]`` (from a Statcast
        export, a dataset, Parquet metadata), possibly none.
    columns : sequence of str, optional
        The columns to compare (default: every shared column of a known unit,
        :data:`UNIT_FACTORS`).
    units : dict, optional
        Units of measured columns, over those the table states.
    permutations, seed, max_rows, plane_rows
        The permutation tests' relabellings, their seed (each column gets its own stream,
        from the seed and its name, so a column's result does not depend on the others
        compared), and the most rows a side they use (subsampled with the seed).
    plane : pair of str or None
        The two columns of the 2-D test (done when both are compared).

    Returns
    -------
    Comparison

    Raises
    ------
    mcbat.errors.InputError
        An empty table, a requested column missing on either side, units that differ and
        cannot be converted, a measured column that looks like another unit than the one
        it is read in, no shared column.
    """
    check_settings(permutations, seed, max_rows, plane_rows, units)
    if len(measured) == 0:
        raise InputError(None, "the measured table has no rows")
    if len(simulated) == 0:
        raise InputError(None, "the simulated dataset has no rows")
    sim_units = dict(simulated.attrs.get("units", {}))
    meas_units = {**measured.attrs.get("units", {}), **(units or {})}
    chosen, not_compared = _choose(simulated, measured, columns, sim_units, meas_units)
    results = []
    for name in chosen:
        result = _compare_column(name, simulated[name], measured[name], sim_units[name],
                                 meas_units.get(name), permutations, seed, max_rows)
        if result is None:
            if columns is not None:
                raise InputError(name, "no finite value on one of the two sides")
            not_compared.append({"column": name, "reason": "no finite value on one side"})
            continue
        results.append(result)
    if not results:
        raise InputError("columns" if columns is not None else None,
                         "no shared column with values on both sides "
                         f"(simulated columns: {len(simulated.columns)}, measured: "
                         f"{', '.join(map(str, measured.columns)) or 'none'})")
    plane_result = None
    compared = {r["column"]: r for r in results}
    if plane is not None and all(c in compared for c in plane):
        plane_result = _compare_plane(plane, simulated, measured, compared, sim_units,
                                      meas_units, permutations, seed, plane_rows)
    settings = {"permutations": int(permutations), "seed": int(seed),
                "p_value_resolution": 1.0 / (1 + permutations) if permutations else None,
                "max_rows": int(max_rows), "plane_rows": int(plane_rows),
                "ks": "scipy.stats.ks_2samp, method auto (exact up to 10,000 rows a side, "
                      "else asymptotic)",
                "energy": "sqrt(2E|X-Y| - E|X-X'| - E|Y-Y'|), permutation p-value "
                          "(1 + k)/(1 + permutations)",
                "plane": "energy distance on coordinates divided by the pooled sample's "
                         "standard deviations, permutation p-value"}
    return Comparison(results, plane_result, not_compared, settings)


def check_settings(permutations, seed, max_rows, plane_rows, units=None):
    """The settings of :func:`compare`, checked (:class:`~mcbat.errors.InputError` naming
    the parameter), before any table is read."""
    for name, unit in (units or {}).items():
        if unit not in UNIT_FACTORS:
            raise InputError("units", f"{name}: unknown unit {unit!r} (known: "
                             f"{', '.join(UNIT_FACTORS)})")
    for name, value, least in (("permutations", permutations, 0), ("seed", seed, 0),
                               ("max_rows", max_rows, 2), ("plane_rows", plane_rows, 2)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                or value < least:
            raise InputError(name, f"must be an integer >= {least}, got {value!r}")
    if permutations > 1_000_000:
        raise InputError("permutations", f"must be <= 1,000,000, got {permutations:,}")
    if seed > 2**63 - 1:
        raise InputError("seed", f"must be <= 2**63 - 1, got {seed}")
    if plane_rows > 5_000:
        raise InputError("plane_rows", f"must be <= 5,000 (the test holds a distance matrix "
                         f"of the pooled rows, 8 (2 x plane_rows)^2 bytes), got {plane_rows:,}")


def _numeric(series):
    import pandas as pd

    return pd.api.types.is_numeric_dtype(series) and not pd.api.types.is_bool_dtype(series)


def _choose(simulated, measured, columns, sim_units, meas_units):
    """The columns to compare, and the shared ones left out with the reason."""
    explicit = columns is not None
    if explicit:
        columns = list(dict.fromkeys(columns))
        if not columns:
            raise InputError("columns", "no column given")
        for name in columns:
            if name not in simulated.columns:
                raise InputError(name, "not a column of the simulated dataset")
            if name not in measured.columns:
                raise InputError(name, "not a column of the measured table (its columns: "
                                 f"{', '.join(map(str, measured.columns))})")
    else:
        columns = [c for c in simulated.columns
                   if c in measured.columns and c not in _NOT_COMPARED]
        if not columns:
            raise InputError(None, "the measured table shares no column with the "
                             "simulated dataset (measured columns: "
                             f"{', '.join(map(str, measured.columns)) or 'none'})")
    chosen, left_out = [], []
    for name in columns:
        reason = _why_not(name, simulated, measured, sim_units, meas_units)
        if reason is None:
            chosen.append(name)
        elif explicit:
            raise InputError(name, reason)
        else:
            left_out.append({"column": name, "reason": reason})
    if not chosen:
        raise InputError(None, "no shared column can be compared: " + "; ".join(
            f"{c['column']}: {c['reason']}" for c in left_out))
    return chosen, left_out


def _why_not(name, simulated, measured, sim_units, meas_units):
    unit = sim_units.get(name)
    if unit not in UNIT_FACTORS:
        return f"the simulated column's unit {unit!r} is not a physical unit mcbat converts"
    if not (_numeric(simulated[name]) and _numeric(measured[name])):
        return "not numbers on both sides"
    stated = meas_units.get(name)
    if stated is None:
        return None
    if stated not in UNIT_FACTORS:
        return (f"the measured table states the unit {stated!r}, which mcbat cannot convert "
                f"to the simulated {unit!r}")
    if UNIT_FACTORS[stated][0] != UNIT_FACTORS[unit][0]:
        return (f"units differ: measured {stated} ({UNIT_FACTORS[stated][0]}), simulated "
                f"{unit} ({UNIT_FACTORS[unit][0]})")
    return None


def _column_values(name, sim_series, meas_series, sim_unit, meas_unit):
    """Both sides' finite values in the unit of comparison (the measured table's stated
    unit, else the simulated one), the unit, the unit converted from, and the counts of
    dropped rows."""
    sim = sim_series.to_numpy(dtype=float)
    meas = meas_series.to_numpy(dtype=float)
    sim_ok, meas_ok = np.isfinite(sim), np.isfinite(meas)
    unit = meas_unit or sim_unit
    sim_values = convert(sim[sim_ok], sim_unit, unit)
    return sim_values, meas[meas_ok], unit, (None if unit == sim_unit else sim_unit), \
        int((~sim_ok).sum()), int((~meas_ok).sum())


def _compare_column(name, sim_series, meas_series, sim_unit, meas_unit, permutations, seed,
                    max_rows):
    sim, meas, unit, converted, sim_dropped, meas_dropped = _column_values(
        name, sim_series, meas_series, sim_unit, meas_unit)
    if sim.size == 0 or meas.size == 0:
        return None
    if meas_unit is None:
        message = _unit_suspicion(name, sim, meas, unit)
        if message:
            raise InputError(name, message)
    stream = [seed, zlib.crc32(name.encode())]
    rng = np.random.default_rng([*stream, 1])
    sim_cap, meas_cap = _subsample(sim, max_rows, rng), _subsample(meas, max_rows, rng)
    energy = energy_test(sim_cap, meas_cap, permutations, seed=stream)
    energy["rows"] = [int(sim_cap.size), int(meas_cap.size)]
    energy["subsampled"] = bool(sim_cap.size < sim.size or meas_cap.size < meas.size)
    return {"column": name, "unit": unit, "converted_from": converted,
            "units": {"simulated": sim_unit, "measured": meas_unit},
            "simulated": _describe(sim, sim_dropped), "measured": _describe(meas, meas_dropped),
            "ks": ks_test(sim, meas), "wasserstein": wasserstein(sim, meas), "energy": energy}


def _describe(values, dropped):
    return {"rows": int(values.size), "dropped": dropped, "mean": float(values.mean()),
            "median": float(np.median(values)),
            "sd": float(values.std(ddof=1)) if values.size > 1 else None}


def _subsample(values, most, rng):
    if len(values) <= most:
        return values
    return values[np.sort(rng.choice(len(values), most, replace=False))]


def _compare_plane(plane, simulated, measured, compared, sim_units, meas_units,
                   permutations, seed, plane_rows):
    units = [compared[c]["unit"] for c in plane]
    sides = []
    for df, side_units in ((simulated, sim_units), (measured, meas_units)):
        values = np.column_stack([convert(df[c].to_numpy(dtype=float),
                                          side_units.get(c) or u, u)
                                  for c, u in zip(plane, units)])
        sides.append(values[np.isfinite(values).all(axis=1)])
    sim, meas = sides
    if len(sim) == 0 or len(meas) == 0:
        return None
    stream = [seed, zlib.crc32(",".join(plane).encode())]
    rng = np.random.default_rng([*stream, 1])
    sim_cap, meas_cap = _subsample(sim, plane_rows, rng), _subsample(meas, plane_rows, rng)
    result = plane_energy_test(sim_cap, meas_cap, permutations, seed=stream)
    result.update({"columns": list(plane), "units": units,
                   "simulated_rows": int(len(sim_cap)), "measured_rows": int(len(meas_cap)),
                   "simulated_available": int(len(sim)), "measured_available": int(len(meas)),
                   "statistic": "energy distance of the standardized points"})
    return result


# --------------------------------------------------------------------------------------
# reading the two sides


def read_simulated(directory):
    """A dataset directory (``mcbat run``) as a DataFrame with ``attrs["units"]``."""
    from mcbat.dataset.load import load

    return load(directory)


def read_measured(paths, units=None):
    """One or more measured tables, concatenated, with the units they state.

    Each path is a Baseball Savant (Statcast) export or mcbat's tidy Statcast table (read by
    :func:`mcbat.statcast.read`; its balls in play only, named as in a game dataset:
    ``hit_distance_sc`` is ``hit_distance``, the pitch's ``spin_rate`` and approach angles
    are ``pitch_spin_rate``, ``pitch_vertical_approach_angle``,
    ``pitch_horizontal_approach_angle``, and the spray angle of a ball caught in foul
    territory is left out), a dataset directory (``mcbat run``), or a CSV or Parquet table
    whose columns are named as the dataset's. Units: a Statcast table's and a dataset's are
    known; a Parquet table may state them in its schema metadata (key ``units``, JSON
    ``{column: unit}``); ``units`` adds or overrides. A CSV states none: its columns are read
    in the simulated dataset's units, and :func:`compare` refuses one that looks like another
    unit.

    Returns
    -------
    pandas.DataFrame
        ``attrs["units"]`` (the stated units), ``attrs["sources"]`` (per path: ``path``,
        ``kind``, ``rows``, and for a Statcast export ``pitches``).
    """
    import pandas as pd

    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    tables, sources, stated = [], [], None
    for path in paths:
        table, source = _read_one(path)
        table_units = dict(table.attrs.get("units", {}))
        if stated is not None:
            for name in set(table.columns) & set(stated):
                if name in table_units and stated.get(name) not in (None, table_units[name]):
                    raise InputError(name, f"unit {table_units[name]} here, "
                                     f"{stated[name]} in {sources[0]['path']}",
                                     str(path))
        stated = {**table_units, **(stated or {})}
        tables.append(table)
        sources.append(source)
    if len(tables) > 1:
        shared = [c for c in tables[0].columns if all(c in t.columns for t in tables[1:])]
        if not shared:
            raise InputError(None, "the measured tables share no column", str(paths[1]))
        combined = pd.concat([t[shared] for t in tables], ignore_index=True)
    else:
        combined = tables[0]
    combined.attrs = {"units": {**stated, **(units or {})}, "sources": sources}
    return combined


def _read_one(path):
    from mcbat.statcast import balls_in_play, is_statcast, read

    label = os.fspath(path)
    path = Path(label)
    if path.is_dir():
        from mcbat.dataset.load import load

        df = load(path)
        return df, {"path": label, "kind": "dataset", "rows": len(df)}
    if not path.exists():
        raise InputError(None, "no such file or directory", label)
    if is_statcast(path):
        pitches = read(path)
        balls = pitches[balls_in_play(pitches)]
        table = balls[list(_STATCAST_COLUMNS)].rename(columns=_STATCAST_NAMES)
        table = table.reset_index(drop=True).astype(float)
        foul = balls["des"].astype(str).str.contains("in foul territory", regex=False)
        table.loc[foul.to_numpy(), "spray_angle"] = np.nan
        units = {_STATCAST_NAMES.get(c, c): pitches.attrs["units"][c] for c in
                 _STATCAST_COLUMNS}
        table.attrs["units"] = units
        if len(table) == 0:
            raise InputError(None, f"the Statcast export has no ball in play (of "
                             f"{len(pitches):,} pitches)", label)
        return table, {"path": label, "kind": "statcast", "rows": len(table),
                       "pitches": len(pitches),
                       "foul_territory": int(foul.sum())}
    table, units = _read_table(path, label)
    if len(table) == 0:
        raise InputError(None, "the table has no data rows", label)
    table.attrs["units"] = units
    return table, {"path": label, "kind": "table", "rows": len(table)}


def _read_table(path, label):
    """A CSV or Parquet table: its columns (numbers where they parse), stated units."""
    import pandas as pd

    suffix = path.suffix.lower()
    units = {}
    try:
        if suffix in (".parquet", ".pq"):
            import pyarrow.parquet as pq

            table = pd.read_parquet(path)
            meta = pq.read_schema(path).metadata or {}
            if b"units" in meta:
                units = json.loads(meta[b"units"])
                if not isinstance(units, dict):
                    raise ValueError("the 'units' metadata is not a JSON object")
                units = {str(k): str(v) for k, v in units.items()}
        elif suffix in (".csv", ".gz"):
            table = pd.read_csv(path, comment="#", skipinitialspace=True)
        else:
            raise InputError(None, f"unknown table format {suffix or '(none)'!r} (use .csv "
                             "or .parquet, or a dataset directory)", label)
    except InputError:
        raise
    except Exception as err:  # noqa: BLE001 - any parser failure is the file's fault
        raise InputError(None, f"cannot read the table: {err}", label) from None
    table.columns = [str(c).strip() for c in table.columns]
    duplicated = sorted({c for c in table.columns if list(table.columns).count(c) > 1})
    if duplicated:
        raise InputError(duplicated[0], "duplicate column", label)
    return table, units


# --------------------------------------------------------------------------------------
# the figure


def fig_compare(path, simulated, measured, comparison):
    """Histograms of both sides per compared column (densities, with the KS distance and
    Wasserstein distance), and the launch speed / launch angle plane side by side
    (simulated as a 2-D histogram, measured as points on the same axes)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    columns = comparison.columns
    plane = comparison.plane
    per_row = 3
    rows_1d = math.ceil(len(columns) / per_row)
    rows = rows_1d + (1 if plane else 0)
    fig = Figure(figsize=(4.0 * per_row, 3.1 * rows), layout="constrained")
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(rows, per_row * 2)
    for k, c in enumerate(columns):
        ax = fig.add_subplot(grid[k // per_row, 2 * (k % per_row):2 * (k % per_row) + 2])
        sim, meas, unit, *_ = _column_values(c["column"], simulated[c["column"]],
                                             measured[c["column"]], c["units"]["simulated"],
                                             c["units"]["measured"])
        low, high = _shown_range(sim, meas)
        bins = np.linspace(low, high, 31)
        # values beyond the range (each side's outer 0.5 %) are not drawn, not piled into
        # the end bins
        ax.hist(sim, bins=bins, density=True, histtype="stepfilled",
                alpha=0.35, color="C0", label=f"simulated ({sim.size:,})")
        ax.hist(meas, bins=bins, density=True, histtype="step", lw=1.6,
                color="C3", label=f"measured ({meas.size:,})")
        ax.set_xlabel(f"{c['column']} ({unit})")
        ax.set_title(f"KS D = {c['ks']['statistic']:.3f}, W = {c['wasserstein']:.3g} {unit}",
                     fontsize=9)
        ax.tick_params(labelsize=8)
        ax.set_yticks([])
        if k == 0:
            ax.legend(fontsize=7)
    if plane:
        (cx, cy), (ux, uy) = plane["columns"], plane["units"]
        given = {c["column"]: c["units"] for c in columns}
        points = []
        for df, side in ((simulated, "simulated"), (measured, "measured")):
            xy = np.column_stack([convert(df[c].to_numpy(dtype=float),
                                          given[c][side] or u, u)
                                  for c, u in ((cx, ux), (cy, uy))])
            points.append(xy[np.isfinite(xy).all(axis=1)])
        extent = [*_shown_range(points[0][:, 0], points[1][:, 0]),
                  *_shown_range(points[0][:, 1], points[1][:, 1])]
        p_text = _p_text(plane["p_value"], comparison.settings["p_value_resolution"])
        titles = (f"simulated ({len(points[0]):,} rows)",
                  f"measured ({len(points[1]):,} rows); energy distance "
                  f"{plane['distance']:.3f} (standardized), p {p_text}")
        axes = [fig.add_subplot(grid[rows_1d, 0:per_row]),
                fig.add_subplot(grid[rows_1d, per_row:2 * per_row])]
        axes[0].hist2d(points[0][:, 0], points[0][:, 1], bins=50,
                       range=[extent[:2], extent[2:]], cmap="Blues", cmin=1)
        axes[1].scatter(points[1][:, 0], points[1][:, 1], s=6, color="C3", alpha=0.6)
        for ax, title in zip(axes, titles):
            ax.set_title(title, fontsize=9)
            ax.set_xlabel(f"{cx} ({ux})")
            ax.set_ylabel(f"{cy} ({uy})")
            ax.set_xlim(extent[:2])
            ax.set_ylim(extent[2:])
            ax.grid(alpha=0.3)
    path = Path(path)
    fig.savefig(path, dpi=130)
    return path
