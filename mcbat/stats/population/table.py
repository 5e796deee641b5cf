"""The measured side of a population fit (``mcbat.stats.population.fit``): the rows of a tidy
Statcast table it uses, and their pitches written as a study's ``[pitches]`` file."""

from __future__ import annotations

import numpy as np

from mcbat.errors import InputError
from mcbat.study.pitches import IDENTIFIERS, PITCH_KEYS, SWING_KEYS

__all__ = ["FLIGHT_OBSERVABLES", "MEASURED_NAMES", "OBSERVABLES", "PITCH_COLUMNS",
           "REQUIRED_PITCH", "SWING_COLUMNS", "population_table", "write_pitches"]

OBSERVABLES = {"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
               "hit_distance": "ft"}
"""The batted-ball observables a population fit can bin (Statcast's names and units; the
game dataset's ``hit_distance`` is Statcast's ``hit_distance_sc``)."""
FLIGHT_OBSERVABLES = ("hit_distance",)
"""Observables only a study with a ``[flight]`` section simulates."""
MEASURED_NAMES = {"hit_distance": "hit_distance_sc"}
"""Observable -> the tidy Statcast table's name of the measured quantity, where they differ
(read when the table has no column of the observable's own name)."""
PITCH_COLUMNS = {f"pitch.{key}": column for key, column in PITCH_KEYS.items()}
"""Study key -> the table's measured pitch column (mcbat.statcast's tidy names): the keys
a study's ``[pitches]`` draws from the rows (``mcbat.study.pitches.PITCH_KEYS``)."""
SWING_COLUMNS = {f"swing.{key}": column for key, column in SWING_KEYS.items()}
"""Study key -> the table's measured swing column (bat tracking), written for a study whose
``[pitches]`` draws the swing too (``swing = true``; ``mcbat.study.pitches.SWING_KEYS``)."""
REQUIRED_PITCH = ("pitch_speed", "vertical_approach_angle", "horizontal_approach_angle")
"""A row without these is left out (counted): its template could not be conditioned."""


def population_table(df, observables=("launch_speed", "launch_angle"), source=None,
                     swing=False, filters=None):
    """The rows of a tidy Statcast table (``mcbat.statcast.read``) a population fit
    uses, and the counts of rows left out.

    A row is used when it has every observable and the pitch at the plate
    (``REQUIRED_PITCH``) and the batter's side. An observable is read from the column
    of its name, else from Statcast's name for it (``MEASURED_NAMES``:
    ``hit_distance_sc`` for ``hit_distance``); the rows returned hold it under the
    observable's name. A row without a measured distance is left out (``no_hit_distance``)
    when ``hit_distance`` is an observable: in Statcast such a ball went untracked, and its
    launch speed and angle are then not measured either (docs/population.md). With
    ``swing`` (a study that draws the measured swing, ``[pitches] swing = true``) a row
    needs a measured ``bat_speed`` too (``no_bat_speed``). With ``filters`` (the study's
    ``[pitches]`` filters, column -> accepted values) only the rows they select are used,
    so that the fit describes the rows the study draws from (``not_selected``: e.g. the
    foul balls of an export, which have a launch but no ``bb_type``).

    Raises
    ------
    InputError
        A table without an observable's or a pitch column, or without a usable row.
    """
    df = df.copy(deep=False)
    read_from = {}  # observable -> the table's column it is read from
    for name in observables:
        measured = MEASURED_NAMES.get(name)
        if name not in df.columns and measured in df.columns:
            df[name] = df[measured]
            read_from[name] = measured
    for name in (*observables, *REQUIRED_PITCH, "handedness"):
        if name not in df.columns:
            what = ("a batted-ball observable" if name in OBSERVABLES else
                    "the measured pitch each row's template is conditioned on")
            if name in MEASURED_NAMES:
                what += f"; the table has neither {name} nor Statcast's {MEASURED_NAMES[name]}"
            raise InputError(name, f"missing column ({what}); a population fit reads a "
                             "Statcast export or mcbat's tidy table (mcbat statcast)", source)
    ok = np.ones(len(df), bool)
    dropped = {}
    if filters:
        ok = _selected(df, filters, source)
        dropped["not_selected"] = int(np.sum(~ok))
    emptied = observables[0]  # the observable after which fewer than 2 rows are left
    for name in observables:
        good = np.isfinite(df[name].to_numpy(float))
        dropped[f"no_{name}"] = int(np.sum(ok & ~good))
        if ok.sum() >= 2 and (ok & good).sum() < 2:
            emptied = name
        ok &= good
    for name in REQUIRED_PITCH:
        good = np.isfinite(df[name].to_numpy(float))
        dropped[f"no_{name}"] = int(np.sum(ok & ~good))
        ok &= good
    if swing:
        if "bat_speed" not in df.columns:
            raise InputError("bat_speed", "missing column (the measured swing of a study "
                             "with [pitches] swing = true; bat tracking starts in 2024)",
                             source)
        good = np.isfinite(df["bat_speed"].to_numpy(float))
        dropped["no_bat_speed"] = int(np.sum(ok & ~good))
        ok &= good
    good = df["handedness"].isin(["R", "L"]).to_numpy()
    dropped["no_handedness"] = int(np.sum(ok & ~good))
    ok &= good
    if ok.sum() < 2:
        # (named after the observable that emptied the table, as the table names it)
        raise InputError(read_from.get(emptied, emptied),
                         f"no rows with {', '.join(observables)} and the pitch at the "
                         "plate (a table of batted balls is needed)", source)
    return df.loc[ok].reset_index(drop=True), dropped


def _selected(df, filters, source) -> np.ndarray:
    """The rows ``filters`` (column -> accepted values, ``[pitches]``'s) select."""
    import pandas as pd

    ok = np.ones(len(df), bool)
    for key, accepted in filters.items():
        if key not in df.columns:
            raise InputError(f"pitches.{key}", f"the table has no column {key}, by which the "
                             "study's [pitches] selects its rows", source)
        column = df[key]
        if all(isinstance(v, (int, float)) for v in accepted):
            column = pd.to_numeric(column, errors="coerce")
        ok &= column.isin(list(accepted)).to_numpy()
    return ok


def write_pitches(table, path):
    """The table's pitches and measured swings (with ``swing_path_tilt``), NaN where a row
    has none, and ``plate_x``, ``plate_z``, ``swing_length`` and the measured
    ``launch_speed`` and ``launch_angle`` (``[pitches.player_levels]``) where the table has
    them, as a tidy CSV a study's ``[pitches]`` reads."""
    names = (*PITCH_COLUMNS.values(), *SWING_COLUMNS.values(), "handedness", "plate_x",
             "plate_z", "swing_length", "swing_path_tilt", "launch_speed", "launch_angle")
    out = table[[c for c in names if c in table.columns]]
    out = out.copy()
    for name in (*PITCH_COLUMNS.values(), *SWING_COLUMNS.values(), "swing_path_tilt"):
        if name not in out.columns:
            out[name] = np.nan
    for k, name in enumerate(IDENTIFIERS):
        # (identifiers only trace a draw to its pitch; a table without them gets the row)
        out[name] = table[name] if name in table.columns else np.arange(len(table)) + k
    out.to_csv(path, index=False)
