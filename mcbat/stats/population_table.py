"""The measured side of a population fit (:mod:`mcbat.stats.population`): the rows of a tidy
Statcast table it uses, and their pitches written as a study's ``[pitches]`` file."""

from __future__ import annotations

import numpy as np

from mcbat.errors import InputError

__all__ = ["OBSERVABLES", "PITCH_COLUMNS", "REQUIRED_PITCH", "population_table",
           "write_pitches"]

OBSERVABLES = {"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg"}
"""The batted-ball observables a population fit can bin (Statcast's names and units)."""
PITCH_COLUMNS = {"pitch.speed": "pitch_speed",
                 "pitch.vertical_approach_angle": "vertical_approach_angle",
                 "pitch.horizontal_approach_angle": "horizontal_approach_angle",
                 "pitch.spin_rate": "spin_rate", "pitch.spin_axis": "spin_axis"}
"""Study key -> the table's measured pitch column (mcbat.statcast's tidy names)."""
REQUIRED_PITCH = ("pitch_speed", "vertical_approach_angle", "horizontal_approach_angle")
"""A row without these is left out (counted): its template could not be conditioned."""
_IDENTIFIERS = ("game_pk", "at_bat_number", "pitch_number", "pitcher", "batter")


def population_table(df, observables=("launch_speed", "launch_angle"), source=None):
    """The rows of a tidy Statcast table (:func:`mcbat.statcast.read`) a population fit
    uses, and the counts of rows left out.

    A row is used when it has every observable and the pitch at the plate
    (:data:`REQUIRED_PITCH`) and the batter's side.

    Raises
    ------
    InputError
        A table without an observable's or a pitch column, or without a usable row.
    """
    for name in (*observables, *REQUIRED_PITCH, "handedness"):
        if name not in df.columns:
            what = ("a batted-ball observable" if name in OBSERVABLES else
                    "the measured pitch each row's template is conditioned on")
            raise InputError(name, f"missing column ({what}); a population fit reads a "
                             "Statcast export or mcbat's tidy table (mcbat statcast)", source)
    ok = np.ones(len(df), bool)
    dropped = {}
    for name in observables:
        good = np.isfinite(df[name].to_numpy(float))
        dropped[f"no_{name}"] = int(np.sum(ok & ~good))
        ok &= good
    for name in REQUIRED_PITCH:
        good = np.isfinite(df[name].to_numpy(float))
        dropped[f"no_{name}"] = int(np.sum(ok & ~good))
        ok &= good
    good = df["handedness"].isin(["R", "L"]).to_numpy()
    dropped["no_handedness"] = int(np.sum(ok & ~good))
    ok &= good
    if ok.sum() < 2:
        raise InputError(observables[0], f"no rows with {', '.join(observables)} and the "
                         "pitch at the plate (a table of batted balls is needed)", source)
    return df.loc[ok].reset_index(drop=True), dropped


def write_pitches(table, path):
    """The table's pitches as a tidy CSV a study's ``[pitches]`` reads."""
    out = table[[c for c in (*PITCH_COLUMNS.values(), "handedness") if c in table.columns]]
    out = out.copy()
    for name in PITCH_COLUMNS.values():
        if name not in out.columns:
            out[name] = np.nan
    for k, name in enumerate(_IDENTIFIERS):
        # (identifiers only trace a draw to its pitch; a table without them gets the row)
        out[name] = table[name] if name in table.columns else np.arange(len(table)) + k
    out.to_csv(path, index=False)
