"""The hints of the messages of a study's row selection (``mcbat.study.pitches``): what
a filter's column holds, and what would give a study rows to draw from."""

from __future__ import annotations

import numpy as np

__all__ = ["present", "show", "what_would_help"]


def what_would_help(source, keys, excluded, untracked) -> str:
    """The hint of the "no row left" error: that the file has no bat tracking
    (``untracked``), else the fallback for the value most rows lack."""
    lacking = sorted(((excluded[f"without {source.keys[k]}"], k) for k in keys
                      if f"without {source.keys[k]}" in excluded), reverse=True)
    if not lacking:
        return ""
    name = lacking[0][1].split(".")[1]
    if untracked:
        return ("; the file has no bat tracking (Statcast measures the swing from 2024 "
                "on): set pitches.swing = false to draw the swing from [swing], or give "
                "pitches.fallback.bat_speed")
    return f"; give pitches.fallback.{name} for rows without it"


def present(column) -> str:
    """A short list of the values a column holds, for a filter's message."""
    values = [v for v in column if v == v and v != ""]  # (NaN and empty: missing)
    if not values:
        return "no values in that column"
    unique, counts = np.unique(np.asarray(values, object if isinstance(values[0], str)
                                          else np.float64), return_counts=True)
    order = np.argsort(-counts, kind="stable")[:8]
    shown = ", ".join(show(unique[i]) for i in order)
    more = f" and {unique.size - 8} more" if unique.size > 8 else ""
    return f"{shown}{more}"


def show(value) -> str:
    """A filter's value as the user wrote it (an identifier without its ``.0``)."""
    if isinstance(value, str):
        return value
    return f"{int(value)}" if float(value).is_integer() else f"{value!r}"
