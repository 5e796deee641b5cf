"""A pitch given twice: the same ``PITCH_KEY`` in two rows of an export (two overlapping
downloads concatenated). The copies are dropped and counted, or refused with ``strict``."""

from __future__ import annotations

import numpy as np

from mcbat.errors import InputError

__all__ = ["PITCH_KEY", "without_duplicates"]


#: The columns that identify a pitch: a second row with the same values is a copy.
PITCH_KEY = ("game_pk", "at_bat_number", "pitch_number")


def without_duplicates(df, label, lines, strict, keep=False):
    """``df`` without the rows that repeat an earlier pitch (``PITCH_KEY``), counted
    in the report (or ``InputError`` with ``strict``), and the lines of its rows.
    Rows missing a part of the key cannot be told apart and are all kept."""
    if keep:
        return df, lines
    report = dict(df.attrs.get("statcast", {}))
    report.setdefault("left_out", {})
    key = df[list(PITCH_KEY)]
    known = key.notna().all(axis=1).to_numpy()
    repeated = np.zeros(len(df), dtype=bool)
    if known.any():
        repeated[known] = key[known].duplicated(keep="first").to_numpy()
    if not repeated.any():
        df.attrs["statcast"] = report
        return df, lines
    first = int(np.flatnonzero(repeated)[0])
    values = key.iloc[first]
    same = np.flatnonzero(known & (key == values).all(axis=1).to_numpy())[0]
    where = (lambda i: f"line {int(lines[i])}") if lines is not None else \
        (lambda i: f"row {i + 1}")
    pitch = ", ".join(f"{c} {values[c]}" for c in PITCH_KEY)
    if strict:
        raise InputError(None, f"{where(first)}: the pitch of {where(same)} again ({pitch}): "
                         f"{int(repeated.sum()):,} pitch(es) given twice (two overlapping "
                         "downloads concatenated?); read without {strict} to drop the "
                         "copies and count them", label, mentions={"strict": True})
    out = df.loc[~repeated].reset_index(drop=True)
    out.attrs = df.attrs
    report["rows"] = int(len(out))
    report["duplicate_pitches"] = {"rows": int(repeated.sum()), "first": where(first),
                                   "repeats": where(same)}
    report["left_out"] = {**report["left_out"], "duplicate pitches": int(repeated.sum())}
    out.attrs["statcast"] = report
    return out, (None if lines is None else np.asarray(lines)[~repeated])
