"""A simulated dataset against a measured table: two-sample statistics per shared column
and in the launch speed / launch angle plane (``mcbat compare``, ``docs/compare.md``).

``compare`` runs the statistics of ``mcbat.stats.compare.two_sample`` (Kolmogorov-Smirnov,
Wasserstein, energy distance with permutation p-values; the energy distance of the
standardized points in the plane) on two DataFrames (rows with NaN dropped per column and
counted; units checked and converted, ``mcbat.stats.compare.units``).
``read_simulated`` and ``read_measured`` read the inputs
(``mcbat.stats.compare.inputs``), ``fig_compare`` draws the figure
(``mcbat.stats.compare.figure``); all are importable from here.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass, field

import numpy as np

from mcbat.errors import InputError
from mcbat.stats.compare.figure import fig_compare
from mcbat.stats.compare.inputs import read_measured, read_simulated
from mcbat.stats.compare.per_row import PITCH_KEY, draw_rows, per_row_calibration
from mcbat.stats.compare.two_sample import (
    PERMUTATIONS,
    energy_test,
    format_p,
    ks_test,
    plane_energy_test,
    wasserstein,
)
from mcbat.stats.compare.units import (
    UNIT_FACTORS,
    column_values,
    convert,
    unit_contradiction,
    unit_suspicion,
)

__all__ = ["MAX_ROWS", "PERMUTATIONS", "PLANE", "PLANE_ROWS", "UNIT_FACTORS", "Comparison",
           "check_settings", "compare", "convert", "energy_test", "fig_compare", "ks_test",
           "plane_energy_test", "read_measured", "read_simulated", "wasserstein"]

MAX_ROWS = 20_000
"""Each side of a column's energy test is subsampled (seeded, without replacement) to at
most this many rows; the KS statistic and the Wasserstein distance use every row."""
PLANE_ROWS = 2_000
"""Each side of the plane's energy test is subsampled to at most this many rows: the test
holds the pooled sample's distance matrix (4,000 x 4,000 at most, 128 MB)."""
PLANE = ("launch_speed", "launch_angle")
"""The plane compared in two dimensions when both sides have both columns."""
_NOT_COMPARED = ("sample_id", "chunk", "source_row", "batter", "pitcher", *PITCH_KEY)


# --------------------------------------------------------------------------------------
# two tables


@dataclass
class Comparison:
    """What ``compare`` found: ``columns`` (one dict per compared column), ``plane``
    (the launch speed / launch angle test, or None), ``not_compared`` (shared columns left
    out, with the reason), the settings and the two sides' descriptions."""

    columns: list
    plane: dict | None
    not_compared: list
    settings: dict
    simulated: dict = field(default_factory=dict)
    measured: dict = field(default_factory=dict)
    per_row: dict | None = None

    def to_dict(self) -> dict:
        """JSON-ready (every number finite or None)."""
        return {"simulated": self.simulated, "measured": self.measured,
                "settings": self.settings, "columns": self.columns, "plane": self.plane,
                "per_row": self.per_row, "not_compared": self.not_compared}

    def lines(self) -> list:
        """The table ``mcbat compare`` prints."""
        s = self.settings
        out = [f"measured rows compared: the {s['drawn']:,} pitches the dataset drew"] \
            if s.get("drawn") else []
        out += [f"{'column':<32} {'unit':<6} {'n sim':>8} {'n meas':>7} {'median sim':>11} "
               f"{'median meas':>11} {'KS D':>6} {'KS p':>8} {'Wasserst.':>10} "
               f"{'energy':>9} {'perm p':>7}"]
        for c in self.columns:
            sim, meas = c["simulated"], c["measured"]
            out.append(
                f"{c['column']:<32} {c['unit']:<6} {sim['rows']:>8,} {meas['rows']:>7,} "
                f"{sim['median']:>11.4g} {meas['median']:>11.4g} {c['ks']['statistic']:>6.3f} "
                f"{format_p(c['ks']['p_value'], None):>8} {c['wasserstein']:>10.4g} "
                f"{c['energy']['distance']:>9.4g} "
                f"{format_p(c['energy']['p_value'], s['p_value_resolution']):>7}")
        if self.plane is not None:
            p = self.plane
            out.append(f"plane {' x '.join(p['columns'])}: energy distance "
                       f"{p['distance']:.4f} (coordinates / pooled sd "
                       f"{p['scale'][0]:.3g} {p['units'][0]}, {p['scale'][1]:.3g} "
                       f"{p['units'][1]}), permutation p "
                       f"{format_p(p['p_value'], s['p_value_resolution'])}; "
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
        energy = (f"energy from {s['permutations']:,} permutations (seed {s['seed']}), "
                  f"resolution {s['p_value_resolution']:.2g}"
                  if s["p_value_resolution"] is not None else
                  "energy without p-values (0 permutations)")
        out.append(f"p-values: KS from scipy (exact or asymptotic); {energy}; energy tests "
                   f"on at most "
                   f"{s['max_rows']:,} rows a side (plane: {s['plane_rows']:,}), "
                   "subsampled with the seed")
        capped = [c["column"] for c in self.columns if c["energy"]["subsampled"]]
        if capped:
            out.append("subsampled for the energy test: " + ", ".join(capped))
        out.extend(per_row_lines(self.per_row))
        for item in self.not_compared:
            out.append(f"not compared: {item['column']}: {item['reason']}")
        return out


#: Draws a pitch that estimate its tails well (docs/compare.md, "Per row").
DRAWS_ADVISED = 200


def per_row_lines(per_row) -> list:
    """The per-row calibration's lines (none when the sides share no pitch key)."""
    if per_row is None:
        return []
    if "not_judged" in per_row:
        return [f"per row: not judged: {per_row['not_judged']}"]
    if not per_row["met"] or not per_row["columns"]:
        why = ("the dataset was not drawn from these pitches" if not per_row.get("drawn")
               else f"the dataset drew {per_row['drawn']:,} of them, too few times each: "
               f"give the study about {DRAWS_ADVISED} samples a pitch (mcbat run ... "
               f"--samples {DRAWS_ADVISED * per_row['rows']:,})")
        return [f"per row: no measured pitch met by {per_row['min_draws']} draws or more "
                f"(of {per_row['rows']:,}): {why}"]
    low, high = per_row["band95"]
    out = [f"per row: each of {per_row['met']:,} measured pitches (of {per_row['rows']:,}) "
           f"ranked among the draws that met it (median {per_row['draws_per_row']:.0f}); "
           f"an exact model puts 10 % above the 90th percentile and 10 % below the 10th "
           f"(95 %: {100 * low:.1f}-{100 * high:.1f} %)"
           + (f"; the {per_row['rows'] - per_row['met']:,} others (not drawn, or by fewer "
              f"than {per_row['min_draws']} draws) are in the two-sample statistics above "
              "(--drawn leaves out those the dataset did not draw)"
              if per_row["met"] < per_row["rows"] else ""),
           f"  {'column':<30} {'rows':>7} {'above p90':>10} {'below p10':>10}"]
    for c in per_row["columns"]:
        if c["rows"]:
            out.append(f"  {c['column']:<30} {c['rows']:>7,} {100 * c['above_p90']:>9.1f}% "
                       f"{100 * c['below_p10']:>9.1f}%")
    by = per_row.get("by")
    for c in per_row["columns"] if by else ():
        unit = f" ({by['unit']})" if by["unit"] else ""
        out.append(f"  {c['column']} ({c['unit']}) by {by['column']}{unit}: measured mean +- "
                   "its standard error, the model's mean of the rows' own draws")
        out.append(f"    {'bin':<16} {'rows':>6} {'measured':>16} {'model':>9} "
                   f"{'above p90':>10} {'below p10':>10}")
        for b in c.get("bins", []):
            se = f"{b['se']:.1f}" if b["se"] is not None else "-"
            out.append(f"    {b['bin']:<16} {b['rows']:>6,} {b['measured']:>9.1f} +- "
                       f"{se:<5} {b['model']:>8.1f} {100 * b['above_p90']:>9.1f}% "
                       f"{100 * b['below_p10']:>9.1f}%")
    return out


def compare(simulated, measured, columns=None, *, units=None, permutations=PERMUTATIONS,
            seed=0, max_rows=MAX_ROWS, plane_rows=PLANE_ROWS, plane=PLANE, by=None,
            drawn=False):
    """Two-sample statistics of ``simulated`` against ``measured`` on their shared columns.

    Parameters
    ----------
    simulated : pandas.DataFrame
        A dataset (``mcbat.load``), its units in ``attrs["units"]``.
    measured : pandas.DataFrame
        The measured rows; the units it states in ``attrs["units"]`` (from a Statcast
        export, a dataset, Parquet metadata), possibly none.
    columns : sequence of str, optional
        The columns to compare (default: every shared column of a known unit,
        ``UNIT_FACTORS``).
    units : dict, optional
        Units of measured columns, over those the table states.
    permutations, seed, max_rows, plane_rows
        The permutation tests' relabellings, their seed (each column gets its own stream,
        from the seed and its name, so a column's result does not depend on the others
        compared), and the most rows a side they use (subsampled with the seed).
    plane : pair of str or None
        The two columns of the 2-D test (done when both are compared).
    by : (str, sequence of float or None), optional
        With a dataset drawn from the measured pitches, a measured column and the inner
        edges of its bins (None: the quintiles of its values), the per-row judgement by
        bin (``mcbat.stats.compare.per_row``).
    drawn : bool
        Compare only the measured pitches the dataset drew (by ``game_pk``,
        ``at_bat_number``, ``pitch_number``): a study's own rows of an export, without the
        balls in play its filters left out.

    Returns
    -------
    Comparison

    Raises
    ------
    mcbat.errors.InputError
        An empty table, a requested column missing on either side, units that differ and
        cannot be converted, a measured column that looks like another unit than the one
        it is read in (stating no unit), a stated unit the values contradict
        (``mcbat.stats.compare.units.unit_contradiction``), no shared column.
    """
    check_settings(permutations, seed, max_rows, plane_rows, units)
    if drawn:
        measured = _drawn(simulated, measured)
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
                         "standard deviations, permutation p-value",
                "drawn": len(measured) if drawn else None}
    per_row = per_row_calibration(
        simulated, measured, {r["column"]: (sim_units[r["column"]], meas_units.get(r["column"]))
                              for r in results}, seed=seed, by=_bins_by(by, measured))
    return Comparison(results, plane_result, not_compared, settings, per_row=per_row)


def _drawn(simulated, measured):
    """The measured rows the simulated dataset drew, ``attrs`` kept."""
    row = draw_rows(simulated, measured)
    if row is None:
        raise InputError("drawn", "needs the pitch identifiers (game_pk, at_bat_number, "
                         "pitch_number) on both sides: a dataset of a study that draws "
                         "its pitches from an export ([pitches] file), and the export")
    if isinstance(row, str):
        raise InputError("drawn", row)
    kept = measured.iloc[np.flatnonzero(np.bincount(row[row >= 0],
                                                    minlength=len(measured)))]
    if len(kept) == 0:
        raise InputError("drawn", "the dataset drew none of the measured pitches")
    out = kept.reset_index(drop=True)
    out.attrs = dict(measured.attrs)
    return out


def _bins_by(by, measured):
    """``by`` checked: ``(column, inner edges)``, the quintiles of the measured values when
    no edges are given."""
    if by is None:
        return None
    name, edges = by
    if name not in measured.columns:
        raise InputError("by", f"{name!r} is not a column of the measured table (its "
                         f"columns: {', '.join(map(str, measured.columns))})")
    values = measured[name].to_numpy(float) if _numeric(measured[name]) else None
    if values is None or not np.isfinite(values).any():
        raise InputError("by", f"{name!r} has no measured numbers to bin")
    if edges is None:
        quintiles = np.quantile(values[np.isfinite(values)], [0.2, 0.4, 0.6, 0.8])
        edges = np.unique([float(f"{q:.3g}") for q in quintiles])
    edges = np.asarray(edges, float)
    if edges.size == 0 or not np.isfinite(edges).all() or np.any(np.diff(edges) <= 0):
        raise InputError("by", f"the bin edges must be finite and increasing, got "
                         f"{', '.join(f'{e:g}' for e in edges) or 'none'}")
    return name, edges


def check_settings(permutations, seed, max_rows, plane_rows, units=None):
    """The settings of ``compare``, checked (``mcbat.errors.InputError`` naming
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


def _compare_column(name, sim_series, meas_series, sim_unit, meas_unit, permutations, seed,
                    max_rows):
    sim, meas, unit, converted, sim_dropped, meas_dropped = column_values(
        name, sim_series, meas_series, sim_unit, meas_unit)
    if sim.size == 0 or meas.size == 0:
        return None
    if meas_unit is None:
        suspicion = unit_suspicion(name, sim, meas, unit)
        if suspicion is not None:
            raise suspicion
    else:
        contradiction = unit_contradiction(name, meas, meas_unit)
        if contradiction is not None:
            raise contradiction
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

