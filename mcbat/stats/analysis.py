"""Common cuts of an impact dataset (pandas).

>>> import mcbat
>>> df = mcbat.load("results/example")
>>> mcbat.stats.analysis.binned(df, "scattering_angle", "exit_speed", bins=24)
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from mcbat.core.status import ImpactStatus
from mcbat.errors import InputError

__all__ = ["binned", "end_state_fractions", "ok_rows"]


def ok_rows(df: pd.DataFrame) -> pd.DataFrame:
    """Rows the solver solved (``status == 0``); failed rows carry NaN outputs."""
    status = df["status"]
    categorical = isinstance(status.dtype, pd.CategoricalDtype)
    ok = status == "ok" if categorical else status == ImpactStatus.OK
    return df[ok]


def binned(df: pd.DataFrame, x: str, y: str, bins=20, quantiles=(0.16, 0.5, 0.84),
           range_=None) -> pd.DataFrame:
    """Quantiles of ``y`` in bins of ``x`` (failed rows excluded).

    Parameters
    ----------
    df : DataFrame
        A dataset (see ``mcbat.load``).
    x, y : str
        Column names, e.g. ``"scattering_angle"`` and ``"exit_speed"``.
    bins : int or sequence of float
        Number of equal-width bins over ``range_`` (default: the data's range), or edges.
    quantiles : sequence of float
        Quantiles of ``y`` per bin; the default gives the median and the 16-84 % band.

    Returns
    -------
    DataFrame
        One row per non-empty bin: ``x_low``, ``x_high``, ``x_center``, ``count``,
        ``mean`` and one ``q<percent>`` column per quantile (``q16``, ``q50``, ``q84``).
    """
    for name in (x, y):
        if name not in df.columns:
            raise InputError(name, "no such column in the dataset")
    data = ok_rows(df)[[x, y]].dropna()
    if np.isscalar(bins):
        lo, hi = range_ if range_ is not None else (data[x].min(), data[x].max())
        edges = np.linspace(lo, hi, int(bins) + 1)
    else:
        edges = np.asarray(bins, float)
    which = pd.cut(data[x], edges, include_lowest=True, labels=False)
    grouped = data.groupby(which)[y]
    table = pd.DataFrame({"count": grouped.size(), "mean": grouped.mean()})
    for q in quantiles:
        table[f"q{round(100 * q):d}"] = grouped.quantile(q)
    index = table.index.to_numpy(dtype=int)
    table.insert(0, "x_low", edges[index])
    table.insert(1, "x_high", edges[index + 1])
    table.insert(2, "x_center", 0.5 * (table["x_low"] + table["x_high"]))
    return table.reset_index(drop=True)


def end_state_fractions(df: pd.DataFrame, by: str | None = None) -> pd.DataFrame:
    """Fractions of stuck, sliding (never stuck) and re-slip end states (solved rows).

    ``by``: an optional column to group by (e.g. the incoming spin).
    """
    data = ok_rows(df)
    end = data["end_state"].astype(str).map({"1": "stuck", "0": "sliding", "stuck": "stuck",
                                             "sliding": "sliding"})
    kind = np.where(end == "stuck", "stuck",
                    np.where(data["stick_impulse"].notna(), "re-slip", "sliding"))
    frame = pd.DataFrame({"kind": kind}, index=data.index)
    if by is None:
        return frame["kind"].value_counts(normalize=True).rename("fraction").to_frame()
    frame[by] = data[by]
    return (frame.groupby(by)["kind"].value_counts(normalize=True).rename("fraction")
            .unstack(fill_value=0.0))
