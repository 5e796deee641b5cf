"""Each measured pitch against the draws that met it: is every row's predictive
distribution calibrated? (``mcbat compare``, ``docs/compare.md``).

A study that draws its pitches from a Statcast export (``[pitches] file``) records, for
every sample, the pitch it met (``game_pk``, ``at_bat_number``, ``pitch_number``). The
draws that met one pitch are that pitch's predictive distribution, and the measured value
is one more draw of it if the model is right. Its rank among them is the probability
integral transform (PIT) of the ensemble forecasting literature (the rank histogram of
Hamill 2001, Mon. Wea. Rev. 129, 550): with ``below`` draws under the measured value,
``equal`` draws at it and ``n`` draws in all,

    u = (below + V (equal + 1)) / (n + 1),    V uniform on (0, 1),

is uniform on (0, 1) for an exact model whatever ``n`` is (the randomisation spreads
ties). "Above the row's 90th percentile" is ``u > 0.9``: an exact model puts 10 % of the
rows there at any number of draws a row. The 90th percentile of numpy's default (linear)
rule taken from the ``n`` draws is exceeded ``(0.1 n + 0.9) / (n + 1)`` of the time by an
exact model instead (13.8 % at 20 draws, 10.5 % at 175), which is why the shares here are
read from ranks.
"""

from __future__ import annotations

import numpy as np

from mcbat.stats.compare.units import convert

__all__ = ["MIN_DRAWS", "PITCH_KEY", "PREDICTED", "TAIL", "draw_rows", "per_row_calibration",
           "probability_integral_transform", "ranks"]

PITCH_KEY = ("game_pk", "at_bat_number", "pitch_number")
"""The columns that name one pitch in a Statcast export and in a dataset drawn from it."""
PREDICTED = ("launch_speed", "launch_angle", "spray_angle")
"""The columns judged per row: what the model predicts from the pitch it met (the pitch's
own columns repeat the measured values and say nothing; Statcast's ``hit_distance_sc``
stops where a fielder first touched the ball, which no flight predicts for a ground
ball)."""
MIN_DRAWS = 10
"""A row met by fewer draws is left out (and counted)."""
TAIL = 0.1
"""The tail share judged on each side: above the 90th percentile, below the 10th."""
MISSING = -1
"""A missing identifier (no real pitch has a negative one); such a row is not joined."""


def probability_integral_transform(draws, value, rng):
    """``u`` of ``value`` among ``draws`` (sorted ascending), ties spread by ``rng``."""
    below = np.searchsorted(draws, value, side="left")
    equal = np.searchsorted(draws, value, side="right") - below
    return (below + rng.random() * (equal + 1)) / (draws.size + 1)


def per_row_calibration(simulated, measured, units=None, *, columns=PREDICTED, seed=0,
                        min_draws=MIN_DRAWS, by=None):
    """The shares of measured rows above their own predictive 90th percentile and below
    their 10th, per predicted column.

    Parameters
    ----------
    simulated : pandas.DataFrame
        A dataset drawn from the measured table's pitches, with :data:`PITCH_KEY`.
    measured : pandas.DataFrame
        The measured rows, with :data:`PITCH_KEY` (a Statcast export read by
        ``read_measured`` has them).
    units : dict
        ``{column: (simulated unit, measured unit)}`` of the columns to judge; a column
        missing here or on either side is not judged.
    columns : sequence of str
        The columns to judge, of those in ``units``.
    seed : int
        Seed of the tie-breaking draws.
    min_draws : int
        The fewest draws a row must meet to be judged.
    by : (str, sequence of float), optional
        A measured column and the inner edges of its bins (``("bat_speed", (65, 70, 75,
        80))``: below 65, 65-70, ..., 80 and above): each judged column's measured and
        model means and shares per bin of the measured rows.

    Returns
    -------
    dict or None
        None when either side lacks the pitch key; ``rows`` and ``not_judged`` (the reason)
        when the measured tables give a pitch twice. Else ``rows`` (measured), ``met`` (rows
        met by at least ``min_draws`` draws), ``drawn`` (rows met by any),
        ``draws_per_row`` (the median over the ``met`` rows), ``expected`` (:data:`TAIL`),
        ``band95`` (the 95 % range of a share of ``met`` rows under an exact model,
        binomial) and ``columns``: per column ``column``, ``unit``,
        ``rows``, ``above_p90``, ``below_p10``, ``histogram`` (the counts of ``u`` in
        ten equal bins) and with ``by`` ``bins``: per bin ``bin`` (its range), ``rows``,
        ``measured`` (the rows' mean), ``se`` (its standard error), ``model`` (the mean of
        the rows' own draw means), ``above_p90``, ``below_p10``. With ``by`` also ``by``
        (the column, its unit, the edges).
    """
    row = draw_rows(simulated, measured)
    if row is None or isinstance(row, str):
        return row if row is None else {"rows": int(len(measured)), "not_judged": row}
    draws = np.bincount(row[row >= 0], minlength=len(measured))
    met = draws >= min_draws
    out = {"rows": int(len(measured)), "met": int(met.sum()), "drawn": int((draws > 0).sum()),
           "draws_per_row": float(np.median(draws[met])) if met.any() else 0.0,
           "min_draws": int(min_draws), "expected": TAIL, "band95": None, "columns": []}
    if not met.any():
        return out
    half = 1.96 * np.sqrt(TAIL * (1 - TAIL) / met.sum())
    out["band95"] = [max(TAIL - half, 0.0), TAIL + half]
    groups = None
    if by is not None:
        by_name, edges = by[0], np.asarray(sorted(by[1]), float)
        where = measured[by_name].to_numpy(float)
        groups = np.where(np.isfinite(where), np.searchsorted(edges, where, side="right"),
                          -1)
        out["by"] = {"column": by_name, "edges": edges.tolist(),
                     "unit": measured.attrs.get("units", {}).get(by_name)}
    for name in columns:
        if name not in (units or {}) or name not in simulated or name not in measured:
            continue
        sim_unit, meas_unit = units[name]
        values = convert(simulated[name].to_numpy(float), sim_unit, meas_unit or sim_unit)
        truth = measured[name].to_numpy(float)
        rows, u = ranks(row, values, truth, min_draws,
                        np.random.default_rng([seed, *name.encode()]))
        judged = _shares(name, meas_unit or sim_unit, u)
        if groups is not None:
            judged["bins"] = _bins(row, values, truth, rows, u, groups, out["by"]["edges"])
        out["columns"].append(judged)
    return out


def draw_rows(simulated, measured):
    """The measured row (from 0) each simulated draw met by :data:`PITCH_KEY` (-1: none),
    None when either side lacks the key, or the reason they cannot be joined (a pitch
    given twice in ``measured``, identifiers that are not whole numbers)."""
    if not all(k in simulated.columns and k in measured.columns for k in PITCH_KEY):
        return None
    import pandas as pd

    measured_key = _whole_numbers(measured[list(PITCH_KEY)])
    simulated_key = _whole_numbers(simulated[list(PITCH_KEY)])
    if measured_key is None or simulated_key is None:
        return (f"the pitch identifiers ({', '.join(PITCH_KEY)}) are not whole numbers on "
                "both sides")
    incomplete = np.flatnonzero((measured_key.to_numpy() == MISSING).any(axis=1))
    measured_key.iloc[incomplete, 0] = MISSING - 1 - np.arange(incomplete.size)  # unmatched
    key = pd.MultiIndex.from_frame(measured_key)
    if key.has_duplicates:
        first = key[key.duplicated()][0]
        return (f"a pitch is given twice in the measured tables (game_pk {first[0]}, "
                f"at_bat_number {first[1]}, pitch_number {first[2]})")
    row = key.get_indexer(pd.MultiIndex.from_frame(simulated_key)).astype(np.int64)
    row[(simulated_key.to_numpy() == MISSING).any(axis=1)] = -1
    return row


def _whole_numbers(frame):
    """The identifier columns as int64, a missing one as :data:`MISSING`; None when a value
    is not a whole number."""
    import pandas as pd

    out = {}
    for name in frame.columns:
        values = pd.to_numeric(frame[name], errors="coerce").to_numpy(float)
        given = frame[name].notna().to_numpy()
        if np.any(given & ~np.isfinite(values)) or np.any(values[given] % 1 != 0):
            return None
        out[name] = np.where(given, values, MISSING).astype(np.int64)
    return pd.DataFrame(out)


def _shares(name, unit, u):
    """One column's shares of its rows' ranks ``u``."""
    if not u.size:
        return {"column": name, "unit": unit, "rows": 0, "above_p90": None,
                "below_p10": None, "histogram": [0] * 10}
    return {"column": name, "unit": unit, "rows": int(u.size),
            "above_p90": float(np.mean(u > 1 - TAIL)), "below_p10": float(np.mean(u < TAIL)),
            "histogram": np.histogram(u, bins=10, range=(0, 1))[0].tolist()}


def _bins(row, values, truth, judged, u, groups, edges):
    """Per bin of the measured rows (``groups``: its index, -1 none) the ``judged`` rows
    (their ranks ``u``), their measured mean and its standard error, the model's mean (of
    the rows' own draw means) and the tail shares."""
    ok = (row >= 0) & np.isfinite(values)
    counts = np.bincount(row[ok], minlength=truth.size)
    row_mean = np.bincount(row[ok], weights=values[ok], minlength=truth.size) / \
        np.maximum(counts, 1)
    labels = ([f"< {edges[0]:g}"] if edges else []) + \
        [f"{lo:g} to {hi:g}" for lo, hi in zip(edges[:-1], edges[1:])] + \
        ([f">= {edges[-1]:g}"] if edges else ["all"])
    out = []
    for k, label in enumerate(labels):
        mine = groups[judged] == k
        rows = judged[mine]
        if not rows.size:
            continue
        out.append({"bin": label, "rows": int(rows.size),
                    "measured": float(truth[rows].mean()),
                    "se": float(truth[rows].std(ddof=1) / np.sqrt(rows.size))
                    if rows.size > 1 else None,
                    "model": float(row_mean[rows].mean()),
                    "above_p90": float(np.mean(u[mine] > 1 - TAIL)),
                    "below_p10": float(np.mean(u[mine] < TAIL))})
    return out


def ranks(row, values, truth, min_draws=MIN_DRAWS, rng=None):
    """``(rows, u)``: the rows ``r`` with a finite measured value ``truth[r]`` and
    ``min_draws`` finite ``values`` of draws whose ``row`` is ``r`` (-1: no measured row),
    ascending, and each one's PIT ``u`` among those draws. ``rng`` breaks ties (default:
    seed 0)."""
    rng = np.random.default_rng(0) if rng is None else rng
    row, values = np.asarray(row), np.asarray(values, float)
    truth = np.asarray(truth, float)
    ok = (row >= 0) & np.isfinite(values)
    order = np.lexsort((values[ok], row[ok]))
    row_sorted, value_sorted = row[ok][order], values[ok][order]
    cuts = np.searchsorted(row_sorted, np.arange(truth.size + 1))
    judged = np.flatnonzero((np.diff(cuts) >= min_draws) & np.isfinite(truth))
    return judged, np.array([probability_integral_transform(
        value_sorted[cuts[r]:cuts[r + 1]], truth[r], rng) for r in judged])
