"""A Statcast export as a measurement table for mcbat's fits (``mcbat fit --data``).

The game fits take Statcast's names and units (``mcbat.stats.measurements``): the
observables ``launch_speed`` (mph), ``launch_angle`` and ``spray_angle`` (deg) and the
measured inputs ``pitch_speed`` (mph, at the plate), ``bat_speed`` (mph) and
``attack_angle`` (deg). This module picks them out of a Savant export (or a tidy table
``mcbat.statcast.write`` wrote) and keeps the rows a fit can use:

- balls in play only (``description`` ``hit_into_play...``): a pitch not put in play has
  no launch;
- with launch speed, launch angle and spray angle all measured;
- not caught in foul territory (Savant's play description ``des`` says "in foul
  territory"): a foul ball caught for an out is put in play, but its spray angle (where it
  was caught: 50-110 deg on the shipped rows) is no fair launch direction. Fair balls
  fielded just beyond the lines (grounders behind the bag, up to ~50 deg) are kept;
- with the plate speed measured (the pitch fit present);
- bat tracking: ``bat_speed`` and ``attack_angle`` are kept as measured inputs when the
  export has them for some ball in play, and then the balls in play without them are
  dropped; an export without bat tracking leaves the swing to the study's scatter.

Everything else in the export is ignored (the pitch's spin, its approach angles, the
distance: the fit's model draws those from the study). What was dropped, and why, is
counted in ``table.attrs["statcast"]``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mcbat.statcast.collision import COLLISION_UNITS
from mcbat.statcast.reader import COLUMNS, REQUIRED, balls_in_play, read_with_lines

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["FIT_COLUMNS", "is_statcast", "measurement_table"]

FIT_COLUMNS = ("launch_speed", "launch_angle", "spray_angle", "pitch_speed", "bat_speed",
               "attack_angle")
"""The columns of a Statcast measurement table, in this order (those present)."""
_OBSERVED = ("launch_speed", "launch_angle", "spray_angle")


def is_statcast(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` (CSV, ``.csv.gz`` or Parquet) is a Savant export or a tidy table,
    judged by its header alone: Savant's required columns, or the tidy table's columns.
    False for anything unreadable (the caller's own reader then reports the problem)."""
    import csv
    import gzip

    path = Path(os.fspath(path))
    try:
        if path.suffix.lower() in (".parquet", ".pq"):
            import pyarrow.parquet as pq

            names = set(pq.read_schema(path).names)
        else:
            opener = gzip.open if path.suffix.lower() == ".gz" else open
            with opener(path, "rt", encoding="utf-8-sig", newline="") as handle:
                names = {c.strip() for c in next(csv.reader(handle), [])}
    except Exception:  # noqa: BLE001 - not ours to judge: the caller reads it again
        return False
    return set(REQUIRED) <= names or set(COLUMNS) - set(COLLISION_UNITS) <= names


def measurement_table(source: str | os.PathLike[str] | pd.DataFrame, *,
                      name: str | None = None) -> pd.DataFrame:
    """The fit's measurement table from a Savant export (see the module docstring).

    Parameters
    ----------
    source : str, os.PathLike or pandas.DataFrame
        Anything ``mcbat.statcast.read`` takes.
    name : str, optional
        How errors and the report name the input.

    Returns
    -------
    pandas.DataFrame
        Float columns of ``FIT_COLUMNS`` (those the export has), every value finite;
        ``attrs["source"]``, and ``attrs["statcast"]``: ``rows`` (pitches in the export),
        ``used``, and the rows dropped: ``not_in_play``, ``no_launch`` (in play without
        launch speed, angle or spray angle), ``foul_territory`` (caught in foul territory),
        ``no_plate_speed``,
        ``no_bat_tracking``; ``measured_inputs``; ``left_out`` (the reader's, pitches given
        twice, when there are any).
    """
    import pandas as pd

    df, lines = read_with_lines(source, name=name)
    label = df.attrs["statcast"]["source"]
    bip = balls_in_play(df)
    launch = np.all([np.isfinite(df[c].to_numpy(dtype=float)) for c in _OBSERVED], axis=0)
    fair = ~df["des"].astype(str).str.contains("in foul territory", regex=False).to_numpy()
    plate = np.isfinite(df["pitch_speed"].to_numpy(dtype=float))
    swing = [c for c in ("bat_speed", "attack_angle")
             if np.isfinite(df.loc[bip, c].to_numpy(dtype=float)).any()]
    tracked = (np.all([np.isfinite(df[c].to_numpy(dtype=float)) for c in swing], axis=0)
               if swing else np.ones(len(df), dtype=bool))
    keep = bip & launch & fair & plate & tracked
    columns = [c for c in FIT_COLUMNS if c in (*_OBSERVED, "pitch_speed", *swing)]
    table = pd.DataFrame({c: df.loc[keep, c].to_numpy(dtype=float) for c in columns})
    table.attrs["source"] = label
    # the file line of each row (a CSV export), for messages about a row
    table.attrs["lines"] = None if lines is None else [int(x) for x in lines[keep]]
    table.attrs["statcast"] = {
        "rows": int(len(df)), "used": int(keep.sum()),
        "not_in_play": int((~bip).sum()),
        "no_launch": int((bip & ~launch).sum()),
        "foul_territory": int((bip & launch & ~fair).sum()),
        "no_plate_speed": int((bip & launch & fair & ~plate).sum()),
        "no_bat_tracking": int((bip & launch & fair & plate & ~tracked).sum()),
        "measured_inputs": [c for c in columns if c not in _OBSERVED],
    }
    if df.attrs["statcast"].get("left_out"):  # the reader's: pitches given twice
        table.attrs["statcast"]["left_out"] = dict(df.attrs["statcast"]["left_out"])
    return table
