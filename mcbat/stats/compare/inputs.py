"""The two sides of a comparison read as DataFrames with their units: a simulated dataset,
and measured tables (a Statcast export, mcbat's tidy Statcast table, a dataset, a CSV or
Parquet table; ``mcbat compare``, ``docs/compare.md``)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from mcbat.errors import InputError
from mcbat.stats.compare.per_row import PITCH_KEY

__all__ = ["read_measured", "read_simulated"]

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
_STATCAST_CONTEXT = ("plate_x", "plate_z", "swing_length", "swing_path_tilt")
"""Measured columns a dataset does not have, kept to bin the per-row judgement by
(``--by``)."""


def read_simulated(directory):
    """A dataset directory (``mcbat run``) as a DataFrame with ``attrs["units"]``."""
    from mcbat.dataset.load import load

    return load(directory)


def read_measured(paths, units=None, *, strict=False):
    """One or more measured tables, concatenated, with the units they state.

    Each path is a Baseball Savant (Statcast) export or mcbat's tidy Statcast table (read by
    ``mcbat.statcast.read``; its balls in play only, named as in a game dataset:
    ``hit_distance_sc`` is ``hit_distance``, the pitch's ``spin_rate`` and approach angles
    are ``pitch_spin_rate``, ``pitch_vertical_approach_angle``,
    ``pitch_horizontal_approach_angle``, and the spray angle of a ball caught in foul
    territory is left out), a dataset directory (``mcbat run``), or a CSV or Parquet table
    whose columns are named as the dataset's. Units: a Statcast table's and a dataset's are
    known; a Parquet table may state them in its schema metadata (key ``units``, JSON
    ``{column: unit}``); ``units`` adds or overrides. A CSV states none: its columns are read
    in the simulated dataset's units, and ``compare`` refuses one that looks like another
    unit.

    Returns
    -------
    pandas.DataFrame
        ``attrs["units"]`` (the stated units), ``attrs["sources"]`` (per path: ``path``,
        ``kind``, ``rows``, and for a Statcast export ``pitches`` and ``left_out`` (the
        pitches not used, by reason: not in play, duplicate pitches).
    """
    import pandas as pd

    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    tables, sources, stated = [], [], None
    for path in paths:
        table, source = _read_one(path, strict)
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


def _read_one(path, strict=False):
    from mcbat.statcast import balls_in_play, is_statcast, read
    from mcbat.statcast.files import check_expansion

    label = os.fspath(path)
    path = Path(label)
    if path.is_dir():
        from mcbat.dataset.load import load

        df = load(path)
        return df, {"path": label, "kind": "dataset", "rows": len(df)}
    if not path.exists():
        raise InputError(None, "no such file or directory", label)
    check_expansion(path, label)  # (is_statcast reads a header line without a limit)
    if is_statcast(path):
        pitches = read(path, strict=strict)
        balls = pitches[balls_in_play(pitches)]
        kept = [*_STATCAST_COLUMNS, *(c for c in _STATCAST_CONTEXT if c in balls)]
        table = balls[kept].rename(columns=_STATCAST_NAMES)
        table = table.reset_index(drop=True).astype(float)
        for name in PITCH_KEY:  # (per-row calibration joins a dataset's draws on them)
            table[name] = balls[name].to_numpy()
        foul = balls["des"].astype(str).str.contains("in foul territory", regex=False)
        table.loc[foul.to_numpy(), "spray_angle"] = np.nan
        units = {_STATCAST_NAMES.get(c, c): pitches.attrs["units"][c] for c in kept}
        table.attrs["units"] = units
        if len(table) == 0:
            raise InputError(None, f"the Statcast export has no ball in play (of "
                             f"{len(pitches):,} pitches)", label)
        left_out = {"not in play": int(len(pitches) - len(balls)),
                    **pitches.attrs["statcast"].get("left_out", {})}
        return table, {"path": label, "kind": "statcast", "rows": len(table),
                       "pitches": len(pitches),
                       "foul_territory": int(foul.sum()), "left_out": left_out}
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
    with path.open("rb") as handle:
        magic = handle.read(4)
    if magic == b"PAR1":
        suffix = ".parquet"  # a Parquet file, whatever its name
    elif magic[:2] == b"\x1f\x8b":
        suffix = ".gz"
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
            table = pd.read_csv(_text_source(path, label), comment="#",
                                skipinitialspace=True)
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


def _text_source(path, label):
    """What pandas reads a CSV table from: the path, or for a gzip file its text
    decompressed under the cap of ``mcbat.statcast.files``."""
    import gzip
    import io

    from mcbat.statcast.files import CappedReader

    with path.open("rb") as handle:
        if handle.read(2) != b"\x1f\x8b":
            return path
    with path.open("rb") as raw:
        stream = CappedReader.for_file(gzip.GzipFile(fileobj=raw), path.stat().st_size,
                                       label)
        return io.BytesIO(stream.read())
