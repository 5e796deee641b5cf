"""What a cell of a Statcast export becomes: numbers with their missing markers and the
cells that are none, identifiers checked, text and dates; each function takes a column
and, for its report, the file line of each row (None for a DataFrame: its row).

Used by ``mcbat.statcast.reader``, which builds the tidy table from them.
"""

from __future__ import annotations

import math

import numpy as np

from mcbat.errors import InputError

__all__ = ["MAX_IDENTIFIER", "MISSING_MARKERS", "check_identifiers", "dates", "integers",
           "numbers", "out_of_range", "text"]

MISSING_MARKERS = ("", "null", "NULL", "NA", "<NA>", "NaN", "nan", "None")
"""Cells that are a missing value: Savant wrote ``null`` in older exports and writes
empty cells now; pandas writes ``NaN``/``<NA>`` when a DataFrame is saved."""


def numbers(values, lines):
    """A column as float64: missing markers NaN, other non-numbers NaN and counted.

    Returns the array and ``None`` or ``{"cells": count, "line": first line (CSV only),
    "value": its text}``.
    """
    import pandas as pd

    series = values
    if pd.api.types.is_bool_dtype(series):
        # True/False is no measurement: pandas would make it 1.0/0.0
        out = np.full(len(series), np.nan)
        bad = np.array(series.notna().to_numpy(), dtype=bool)
    else:
        flags = np.array([isinstance(v, (bool, np.bool_)) for v in series.tolist()],
                         dtype=bool) if series.dtype == object else None
        if flags is not None and flags.any():
            series = series.where(~flags, None)
        converted = pd.to_numeric(series, errors="coerce")
        out = np.array(converted.to_numpy(dtype=float, na_value=np.nan))
        if not pd.api.types.is_numeric_dtype(series):
            given = np.array(series.notna().to_numpy(), dtype=bool)
            if given.any():
                stripped = series[given].astype(str).str.strip()
                given[given] = ~stripped.isin(MISSING_MARKERS).to_numpy()
            bad = given & np.isnan(out)
        else:
            bad = np.zeros(len(out), dtype=bool)
        if flags is not None and flags.any():
            bad |= flags
            series = values
    # inf is not a measurement either
    infinite = np.isinf(out)
    bad |= infinite
    out[infinite] = np.nan
    if not bad.any():
        return out, None
    first = int(np.flatnonzero(bad)[0])
    report = {"cells": int(bad.sum()), "value": str(series.iloc[first])}
    if lines is not None:
        report["line"] = int(lines[first])
    else:
        report["row"] = first + 1
    return out, report


def out_of_range(values, bounds, lines):
    """Set the values outside ``bounds`` to NaN (in place); None or ``{"cells", "line"
    (CSV) or "row", "value", "range"}`` of the first."""
    low, high = bounds
    with np.errstate(invalid="ignore"):
        far = (values < low) | (values > high)
    if not far.any():
        return None
    first = int(np.flatnonzero(far)[0])
    report = {"cells": int(far.sum()), "value": f"{values[first]:.6g}",
              "range": [low, high]}
    if lines is not None:
        report["line"] = int(lines[first])
    else:
        report["row"] = first + 1
    values[far] = np.nan
    return report


#: Identifiers are whole numbers from 0 to this (2**53: every such integer is exact in the
#: float64 the reader parses numbers into; MLBAM ids are below 10**7).
MAX_IDENTIFIER = 2**53


def check_identifiers(columns, label, lines):
    """``InputError`` naming the column and line (or row) of the first identifier that
    is not a whole number in 0..``MAX_IDENTIFIER`` (missing values are allowed)."""
    import pandas as pd

    for column, values in columns.items():
        x = pd.to_numeric(pd.Series(values), errors="coerce").to_numpy(dtype=float,
                                                                        na_value=np.nan)
        given = ~np.isnan(x)
        with np.errstate(invalid="ignore"):
            bad = given & ~(np.isfinite(x) & (x >= 0) & (x <= MAX_IDENTIFIER)
                            & (x == np.round(x)))
        if not bad.any():
            continue
        i = int(np.flatnonzero(bad)[0])
        where = f"line {int(lines[i])}" if lines is not None else f"row {i + 1}"
        value = x[i]
        shown = (f"{int(value)}" if np.isfinite(value) and value == np.round(value)
                 and abs(value) < 1e21 else f"{value:.17g}")
        reason = ("not a whole number" if np.isfinite(value) and value == value
                  and 0 <= value <= MAX_IDENTIFIER else
                  f"outside 0..2**53 = {MAX_IDENTIFIER:,}")
        raise InputError(column, f"{where}: {shown} is not an identifier ({reason}); "
                         f"{int(bad.sum()):,} such row(s)", label)


def integers(values):
    """Identifiers as nullable integers (NaN where missing or not a whole number)."""
    import pandas as pd

    whole = np.where(np.isfinite(values) & (values == np.round(values)), values, np.nan)
    return pd.array(whole, dtype="Int64")


def text(values):
    """A text column as Python strings with NaN where missing (object dtype, so that
    ``df.pitch_type == "FF"`` is False, not NA, on a missing value)."""
    out = np.empty(len(values), dtype=object)
    for i, value in enumerate(values.tolist()):
        if value is None or (isinstance(value, float) and math.isnan(value)):
            out[i] = np.nan
            continue
        value = str(value).strip()
        out[i] = np.nan if value in MISSING_MARKERS else value
    return out


def dates(values):
    """A date column as normalised datetimes (NaT where it is not a date)."""
    import pandas as pd

    return pd.to_datetime(values, errors="coerce", format="mixed").dt.normalize() \
        if len(values) else pd.Series([], dtype="datetime64[ns]")
