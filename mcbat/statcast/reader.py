"""Read a Baseball Savant export (CSV, or a pybaseball DataFrame) into mcbat's tidy table.

One row per pitch, in mcbat's field frame and units (``docs/statcast.md`` lists every
column with its unit and definition; ``UNITS`` is the machine-readable list).
Missing values stay NaN; nothing is guessed. What the reader does with imperfect input:

============================================  =============================================
input                                         result
============================================  =============================================
not a Savant export (required columns absent) ``mcbat.errors.InputError`` naming
                                              the missing columns (exit 2 in the CLI)
a row with more or fewer fields than the      ``mcbat.errors.InputError`` naming the
header; an unterminated quote (a truncated    line: the file was cut or is malformed
download)
not UTF-8 text, an empty file                 ``mcbat.errors.InputError``
a non-numeric cell in a numeric column        NaN, counted per column with the first
(``"abc"`` for ``launch_speed``)              offending line in ``attrs["statcast"]
                                              ["non_numeric"]``
Savant's ``null`` marker, empty cells         NaN (not counted: that is how Savant writes
                                              a missing value)
an optional column the season lacks           a column of NaN, listed in
(``spin_axis`` before 2020, bat tracking       ``attrs["statcast"]["missing_columns"]``
before 2024, ...)
a ``home_team`` (or date) the park table does  NaN elevation, counted in
not know                                      ``attrs["statcast"]["elevation_missing"]``
a column named twice (Savant writes           the first one is used (the copies hold the
``pitcher`` and ``fielder_2`` twice)          same values in Savant's exports)
a pitch given twice (the same ``game_pk``,    the copy dropped, counted in ``attrs["statcast"]
``at_bat_number`` and ``pitch_number``: two   ["left_out"]`` and ``["duplicate_pitches"]``
overlapping downloads concatenated)           (with its line); ``strict=True``: InputError
the header line again inside the file         :class:`~mcbat.errors.InputError` naming its line
an identifier that is not a whole number in   :class:`~mcbat.errors.InputError` naming the
0..2**53 (``game_pk`` 9223372036854775808,    column and the line (a DataFrame: the row)
``batter`` 1.5)
a number outside the range of a measurement   NaN, counted per column with the first line in
(:data:`RANGES`: ``launch_speed`` 1e20)       ``attrs["statcast"]["out_of_range"]``
a bool cell in a numeric column (a            NaN, counted in ``non_numeric``: True is no
DataFrame)                                    measurement
a directory, a FIFO, a device                 :class:`~mcbat.errors.InputError` saying what it
                                              is, before anything is opened
a gzip file expanding beyond 50 times its     :class:`~mcbat.errors.InputError` naming the cap
size (at least 64 MiB); a line over 16 MiB    (:mod:`mcbat.statcast.files`)
a Parquet file named ``.csv``                 read as Parquet (told by its magic bytes)
============================================  =============================================
"""

from __future__ import annotations

import contextlib
import contextvars
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from mcbat.errors import InputError
from mcbat.statcast import cells, kinematics, parks
from mcbat.statcast.collision import COLLISION_UNITS, collision_columns
from mcbat.statcast.csv_rows import csv_chunks
from mcbat.statcast.duplicates import PITCH_KEY, without_duplicates
from mcbat.statcast.files import check_regular_file, write_parquet
from mcbat.statcast.plays import balls_in_play

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["COLUMNS", "METADATA_KEY", "OPTIONAL", "PITCH_KEY", "RANGES", "REQUIRED", "UNITS",
           "balls_in_play", "read", "read_with_lines", "write"]

UNITS = {
    # identifiers
    "game_pk": "id", "at_bat_number": "1", "pitch_number": "1", "batter": "id",
    "pitcher": "id",
    # where and when
    "game_date": "date", "game_year": "year", "home_team": "code", "elevation": "ft",
    # the pitch
    "pitch_type": "code", "p_throws": "code (R, L)", "handedness": "code (R, L)",
    "release_speed": "mph", "pitch_speed": "mph", "vertical_approach_angle": "deg",
    "horizontal_approach_angle": "deg", "spin_rate": "rpm", "spin_axis": "deg",
    "plate_x": "ft", "plate_z": "ft",
    # the swing (bat tracking, 2024-)
    "bat_speed": "mph", "swing_length": "ft", "attack_angle": "deg",
    "attack_direction": "deg", "swing_path_tilt": "deg",
    # the batted ball
    "description": "code", "events": "code", "des": "text", "bb_type": "code",
    "launch_speed": "mph",
    "launch_angle": "deg", "spray_angle": "deg", "hit_distance_sc": "ft",
    "hit_location": "code (fielder 1-9)", "hc_x": "spray-chart units",
    "hc_y": "spray-chart units",
    # the collision measured (tracked balls in play; mcbat.statcast.collision)
    **COLLISION_UNITS,
}
"""Every column of the tidy table, in order, with its unit."""
COLUMNS = tuple(UNITS)
"""The tidy table's columns, in order."""

REQUIRED = ("pitch_type", "game_date", "release_speed", "batter", "pitcher", "events",
            "description", "des", "stand", "p_throws", "home_team", "hit_location", "bb_type",
            "game_year", "plate_x", "plate_z", "hc_x", "hc_y", "vx0", "vy0", "vz0", "ax",
            "ay", "az", "hit_distance_sc", "launch_speed", "launch_angle",
            "release_spin_rate", "game_pk", "at_bat_number", "pitch_number")
"""Columns every Savant pitch-level export has had, whatever the season (2015-2025)."""
OPTIONAL = ("spin_axis", "bat_speed", "swing_length", "attack_angle", "attack_direction",
            "swing_path_tilt")
"""Columns that came later: ``spin_axis`` (2020), ``bat_speed`` and ``swing_length``
(2024), ``attack_angle``, ``attack_direction`` and ``swing_path_tilt`` (2025)."""

_NUMERIC = ("release_speed", "batter", "pitcher", "hit_location", "game_year", "plate_x",
            "plate_z", "hc_x", "hc_y", "vx0", "vy0", "vz0", "ax", "ay", "az",
            "hit_distance_sc", "launch_speed", "launch_angle", "release_spin_rate",
            "game_pk", "at_bat_number", "pitch_number", *OPTIONAL)
#: The range of a numeric cell (in the export's units: mph, ft, ft/s, ft/s^2, deg, rpm)
#: outside which it is no measurement: such a cell is read as NaN and counted per column
#: (``attrs["statcast"]["out_of_range"]``). The ranges are wide (the fastest pitch measured
#: is near 106 mph, the fastest batted ball near 122 mph, the longest drive near 505 ft).
RANGES = {
    "release_speed": (0.0, 150.0), "launch_speed": (0.0, 150.0), "bat_speed": (0.0, 150.0),
    "plate_x": (-20.0, 20.0), "plate_z": (-20.0, 20.0), "hc_x": (-500.0, 1000.0),
    "hc_y": (-500.0, 1000.0), "vx0": (-250.0, 250.0), "vy0": (-250.0, 250.0),
    "vz0": (-250.0, 250.0), "ax": (-150.0, 150.0), "ay": (-150.0, 150.0),
    "az": (-150.0, 150.0), "hit_distance_sc": (0.0, 1000.0), "launch_angle": (-90.0, 90.0),
    "release_spin_rate": (0.0, 10000.0), "hit_location": (1.0, 9.0),
    "game_year": (1900.0, 2100.0), "spin_axis": (0.0, 360.0), "swing_length": (0.0, 20.0),
    "attack_angle": (-90.0, 90.0), "attack_direction": (-180.0, 180.0),
    "swing_path_tilt": (-90.0, 90.0),
}
_TEXT = ("pitch_type", "events", "description", "stand", "p_throws", "home_team",
         "bb_type", "des")
_IDENTIFIERS = ("game_pk", "at_bat_number", "pitch_number", "batter", "pitcher")

METADATA_KEY = b"mcbat.statcast"
"""The Parquet schema-metadata key of a tidy table: JSON with ``units`` and ``statcast``
(the reader's report)."""

_TIDY_MARKER = ("pitch_speed", "vertical_approach_angle", "spray_angle")
_DERIVED = tuple(COLLISION_UNITS)
"""Columns computed from the others: a tidy table written before they existed gets them
when read."""


def read(source: str | os.PathLike[str] | pd.DataFrame, *, name: str | None = None,
         strict: bool = False, keep_duplicates: bool = False) -> pd.DataFrame:
    """Read a Savant export into mcbat's tidy table, one row per pitch.

    Parameters
    ----------
    source : str, os.PathLike or pandas.DataFrame
        A Savant CSV export (``.csv`` or ``.csv.gz``; any season 2015-2025, the columns of
        its year), a Parquet file holding such an export or a table ``write`` wrote
        (told by its content, whatever its name), or a DataFrame (pybaseball's
        ``statcast()`` result, a raw export read by pandas, or a tidy table). A path must
        be a regular file (``mcbat.statcast.files.check_regular_file``).
    name : str, optional
        How errors and the report name the input (default: the path, or
        ``"<DataFrame>"``).
    strict : bool
        Refuse a pitch given twice (the same ``game_pk``, ``at_bat_number`` and
        ``pitch_number``) instead of dropping the copy and counting it.
    keep_duplicates : bool
        Keep every row as it is, copies too (for a caller that numbers the rows as in the
        file and counts the copies itself).

    Returns
    -------
    pandas.DataFrame
        The columns of ``COLUMNS`` (``docs/statcast.md``). ``df.attrs["units"]`` maps
        each column to its unit; ``df.attrs["statcast"]`` is the reader's report:
        ``source``, ``rows`` (pitches kept), ``missing_columns`` (optional columns the
        input lacks, NaN here), ``non_numeric`` (per column: cells that were not numbers,
        set to NaN, and the first one's line and value), ``out_of_range`` (likewise, cells
        outside ``RANGES``), ``elevation_missing`` (rows
        without a park elevation, per ``home_team``), ``unknown_home_teams`` (codes the
        park table does not know, with their rows), ``duplicate_columns``,
        ``duplicate_pitches`` (rows dropped as copies of an earlier pitch, the first one's
        line and the line of the pitch it repeats) and ``left_out`` (rows the reader left
        out, by reason: ``{"duplicate pitches": n}``).

    Raises
    ------
    mcbat.errors.InputError
        One line naming the input and what is wrong: a missing required column, a
        truncated or malformed CSV, a header line repeated inside the file, an identifier
        that is not a whole number in range (naming its column and line), a pitch given
        twice with ``strict``, a file that cannot be read, a path that is not a regular
        file.
    """
    return read_with_lines(source, name=name, strict=strict,
                           keep_duplicates=keep_duplicates)[0]


def read_with_lines(source: str | os.PathLike[str] | pd.DataFrame, *, name: str | None = None,
                    strict: bool = False, keep_duplicates: bool = False
                    ) -> tuple[pd.DataFrame, NDArray[np.int64] | None]:
    """``read``, and the file line (from 1, as an editor counts) of each row of the
    table: an int64 array for a CSV export, None for Parquet or a DataFrame. For messages
    about a row that name the line of the file it came from."""
    import pandas as pd

    if isinstance(source, pd.DataFrame):
        label = name or "<DataFrame>"
        base = [c for c in COLUMNS if c not in _DERIVED]
        if set(base) <= set(map(str, source.columns)) and "vy0" not in source.columns:
            tidy = _with_collision(source[base].copy())  # already a tidy table: as it is
            cells.check_identifiers({c: tidy[c] for c in _IDENTIFIERS}, label, None)
            tidy.attrs["units"] = dict(UNITS)
            tidy.attrs["statcast"] = dict(source.attrs.get("statcast", {"source": label,
                                                                        "rows": len(tidy)}))
            return without_duplicates(tidy, label, None, strict, keep_duplicates)
        raw = source.copy()
        raw.columns = [str(c) for c in raw.columns]
        lines = None
        duplicates = sorted({c for c in raw.columns if list(raw.columns).count(c) > 1})
        raw = raw.loc[:, ~raw.columns.duplicated()]
    else:
        path = Path(os.fspath(source))
        label = name or str(path)
        check_regular_file(path, label)
        if path.suffix.lower() in (".parquet", ".pq") or _is_parquet(path, label):
            raw = _read_parquet(path, label)
            if all(c in raw.columns for c in _TIDY_MARKER):
                return without_duplicates(_tidy_from_parquet(raw, path, label), label,
                                           None, strict, keep_duplicates)
            lines = None
            duplicates = []
        else:
            df, lines = _read_csv_tidy(path, label)
            return without_duplicates(df, label, lines, strict, keep_duplicates)
    return without_duplicates(_tidy(raw, label, lines, duplicates), label, None, strict,
                               keep_duplicates)


def _is_parquet(path, label):
    """Whether the file starts with Parquet's magic bytes (a Parquet file named ``.csv``)."""
    try:
        with path.open("rb") as handle:
            return handle.read(4) == b"PAR1"
    except OSError as err:
        raise InputError(None, f"cannot read the file: {err.strerror or err}", label) from None


def _read_parquet(path, label):
    import pandas as pd

    check_regular_file(path, label)
    try:
        return pd.read_parquet(path)
    except Exception as err:  # noqa: BLE001 - any reader failure is the file's fault
        raise InputError(None, f"cannot read the Parquet file: {err}", label) from None


#: Rows the CSV reader parses at a time: a season's export (~700,000 pitches, ~400 MB) is
#: read in pieces, so that the text of only one piece is in memory with the tidy table.
CHUNK_ROWS = 100_000


def _csv_chunks(path, label, rows=None):
    """The export's columns (``REQUIRED``, ``OPTIONAL``) as strings, ``CHUNK_ROWS`` (or
    ``rows``) rows at a time (``mcbat.statcast.csv_rows.csv_chunks``)."""
    return csv_chunks(path, label, (*REQUIRED, *OPTIONAL), _check_required,
                      CHUNK_ROWS if rows is None else rows)


_PROGRESS = contextvars.ContextVar("mcbat_statcast_progress", default=None)


@contextlib.contextmanager
def progress(report):
    """Within the block, ``report(rows, label, done)`` is called after each piece of a CSV
    export is read (rows read so far; ``done`` True once, after the last piece): how a
    command shows its progress on a season's export."""
    token = _PROGRESS.set(report)
    try:
        yield
    finally:
        _PROGRESS.reset(token)


def _read_csv_tidy(path, label):
    """The tidy table of a CSV export, parsed ``CHUNK_ROWS`` rows at a time, and the
    file line of each row."""
    import pandas as pd

    report = _PROGRESS.get()
    parts, reports, all_lines = [], [], []
    rows = 0
    for raw, lines, duplicates in _csv_chunks(path, label):
        part = _tidy(raw, label, lines, duplicates)
        reports.append(part.attrs["statcast"])
        parts.append(part)
        all_lines.append(np.asarray(lines, dtype=np.int64))
        rows += len(part)
        if report is not None:
            report(rows, label, False)
    if report is not None:
        report(rows, label, True)
    df = parts[0] if len(parts) == 1 else pd.concat(parts, ignore_index=True)
    df.attrs["units"] = dict(UNITS)
    df.attrs["statcast"] = _merged_reports(reports)
    return df, np.concatenate(all_lines)


def _merged_reports(reports):
    """One report of the pieces' reports: counts added, the first offending cell kept."""
    out = dict(reports[0])
    out["rows"] = sum(r["rows"] for r in reports)
    for key in ("elevation_missing", "unknown_home_teams"):
        merged = {}
        for r in reports:
            for name, count in r[key].items():
                merged[name] = merged.get(name, 0) + count
        out[key] = merged
    for key in ("non_numeric", "out_of_range"):
        merged = {}
        for r in reports:
            for column, bad in r[key].items():
                if column in merged:
                    merged[column]["cells"] += bad["cells"]
                else:
                    merged[column] = dict(bad)
        out[key] = merged
    return out


def _tidy(raw, label, lines, duplicates):
    import pandas as pd

    _check_required(raw.columns, label)
    n = len(raw)
    report = {"source": label, "rows": n,
              "missing_columns": [c for c in OPTIONAL if c not in raw.columns],
              "non_numeric": {}, "out_of_range": {}, "elevation_missing": {},
              "unknown_home_teams": {},
              "duplicate_columns": duplicates}
    num = {}
    for column in _NUMERIC:
        if column not in raw.columns:
            num[column] = np.full(n, np.nan)
            continue
        num[column], bad = cells.numbers(raw[column], lines)
        if column in _IDENTIFIERS and bad:
            where = f"line {bad['line']}" if "line" in bad else f"row {bad['row']}"
            raise InputError(column, f"{where}: {bad['value']!r} is not an identifier (a "
                             "whole number)", label)
        if bad:
            report["non_numeric"][column] = bad
        if column in RANGES:
            far = cells.out_of_range(num[column], RANGES[column], lines)
            if far:
                report["out_of_range"][column] = far
    cells.check_identifiers({c: num[c] for c in _IDENTIFIERS}, label, lines)
    text = {c: cells.text(raw[c]) for c in _TEXT}

    speed, vertical, horizontal = kinematics.plate_crossing(
        num["vx0"], num["vy0"], num["vz0"], num["ax"], num["ay"], num["az"])
    game_date = cells.dates(raw["game_date"])
    elevation = parks.elevation(text["home_team"], num["game_year"],
                                game_date=np.asarray(game_date, dtype="datetime64[D]"))
    known = {p["home_team"] for p in parks.parks()}
    for team, value in zip(text["home_team"], elevation):
        key = team if isinstance(team, str) else "(missing)"
        if np.isnan(value):
            report["elevation_missing"][key] = report["elevation_missing"].get(key, 0) + 1
        if key not in known:
            report["unknown_home_teams"][key] = report["unknown_home_teams"].get(key, 0) + 1

    columns = {
        **{c: cells.integers(num[c]) for c in _IDENTIFIERS},
        "game_date": game_date,
        "game_year": num["game_year"],
        "home_team": text["home_team"],
        "elevation": elevation,
        "pitch_type": text["pitch_type"],
        "p_throws": text["p_throws"],
        "handedness": text["stand"],
        "release_speed": num["release_speed"],
        "pitch_speed": speed,
        "vertical_approach_angle": vertical,
        "horizontal_approach_angle": horizontal,
        "spin_rate": num["release_spin_rate"],
        "spin_axis": num["spin_axis"],
        "plate_x": num["plate_x"],
        "plate_z": num["plate_z"],
        # Savant's bat-tracking angles are already in mcbat's conventions
        # (docs/statcast.md): attack_direction > 0 towards the batter's opposite field.
        "bat_speed": num["bat_speed"],
        "swing_length": num["swing_length"],
        "attack_angle": num["attack_angle"],
        "attack_direction": num["attack_direction"],
        "swing_path_tilt": num["swing_path_tilt"],
        "description": text["description"],
        "events": text["events"],
        "des": text["des"],
        "bb_type": text["bb_type"],
        "launch_speed": num["launch_speed"],
        "launch_angle": num["launch_angle"],
        "spray_angle": kinematics.spray_angle(num["hc_x"], num["hc_y"]),
        "hit_distance_sc": num["hit_distance_sc"],
        "hit_location": num["hit_location"],
        "hc_x": num["hc_x"],
        "hc_y": num["hc_y"],
    }
    df = _with_collision(pd.DataFrame(columns, columns=[c for c in COLUMNS
                                                        if c not in _DERIVED]))
    df.attrs["units"] = dict(UNITS)
    df.attrs["statcast"] = report
    return df


def _with_collision(df):
    """``df`` with the collision columns (``mcbat.statcast.collision``) computed."""
    for name, values in collision_columns(df, balls_in_play(df)).items():
        df[name] = values
    return df


def _check_required(columns, label):
    """``InputError`` naming the required columns ``columns`` lacks (the first ten
    and their count when most are missing: the file is something else altogether)."""
    missing = [c for c in REQUIRED if c not in set(columns)]
    if not missing:
        return
    if len(missing) > 10:
        named = (f"{len(missing)} of its {len(REQUIRED)} required columns "
                 f"({', '.join(missing[:10])}, ...)")
    else:
        named = f"column{'s' if len(missing) > 1 else ''} {', '.join(missing)}"
    raise InputError(None, f"not a Statcast (Baseball Savant) pitch-level export: missing "
                     f"{named}", label)


def _tidy_from_parquet(table, path, label):
    """A table ``write`` wrote: its columns and the report kept in its metadata."""
    import pyarrow.parquet as pq

    missing = [c for c in COLUMNS if c not in table.columns and c not in _DERIVED]
    if missing:
        raise InputError(None, f"a tidy Statcast table but missing column"
                         f"{'s' if len(missing) > 1 else ''} {', '.join(missing)}", label)
    cells.check_identifiers({c: table[c] for c in _IDENTIFIERS}, label, None)
    table = _with_collision(table[[c for c in COLUMNS if c not in _DERIVED]].copy())
    meta = pq.read_schema(path).metadata or {}
    info = json.loads(meta[METADATA_KEY]) if METADATA_KEY in meta else {}
    table.attrs["units"] = dict(UNITS)
    table.attrs["statcast"] = info.get("statcast", {"source": label, "rows": len(table)})
    return table


def write(df, path):
    """Write a tidy table (from ``read``) to Parquet, atomically, with its units and
    the reader's report in the schema metadata (key ``METADATA_KEY``).

    The file appears complete or not at all: it is written under a temporary name in the
    same directory and renamed.
    """
    info = {"units": dict(UNITS), "statcast": df.attrs.get("statcast", {})}
    write_parquet(df[list(COLUMNS)], path,
                  {METADATA_KEY: json.dumps(info, sort_keys=True).encode()})
