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
import csv
import json
import math
import operator
import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from mcbat.errors import InputError
from mcbat.statcast import kinematics, parks
from mcbat.statcast.collision import COLLISION_UNITS, collision_columns
from mcbat.statcast.files import (
    MAX_LINE_BYTES,
    CappedReader,
    check_regular_file,
    write_parquet,
)
from mcbat.statcast.plays import balls_in_play

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["COLUMNS", "METADATA_KEY", "OPTIONAL", "PITCH_KEY", "RANGES", "REQUIRED", "UNITS",
           "attack_direction_check", "balls_in_play", "read", "read_with_lines", "summarize",
           "write"]

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
_MISSING_MARKERS = ("", "null", "NULL", "NA", "<NA>", "NaN", "nan", "None")
"""Cells that are a missing value: Savant wrote ``null`` in older exports and writes
empty cells now; pandas writes ``NaN``/``<NA>`` when a DataFrame is saved."""

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
            _check_identifiers({c: tidy[c] for c in _IDENTIFIERS}, label, None)
            tidy.attrs["units"] = dict(UNITS)
            tidy.attrs["statcast"] = dict(source.attrs.get("statcast", {"source": label,
                                                                        "rows": len(tidy)}))
            return _without_duplicates(tidy, label, None, strict, keep_duplicates)
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
                return _without_duplicates(_tidy_from_parquet(raw, path, label), label,
                                           None, strict, keep_duplicates)
            lines = None
            duplicates = []
        else:
            df, lines = _read_csv_tidy(path, label)
            return _without_duplicates(df, label, lines, strict, keep_duplicates)
    return _without_duplicates(_tidy(raw, label, lines, duplicates), label, None, strict,
                               keep_duplicates)


def _is_parquet(path, label):
    """Whether the file starts with Parquet's magic bytes (a Parquet file named ``.csv``)."""
    try:
        with path.open("rb") as handle:
            return handle.read(4) == b"PAR1"
    except OSError as err:
        raise InputError(None, f"cannot read the file: {err.strerror or err}", label) from None


#: The columns that identify a pitch: a second row with the same values is a copy.
PITCH_KEY = ("game_pk", "at_bat_number", "pitch_number")


def _without_duplicates(df, label, lines, strict, keep=False):
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
_BLOCK_BYTES = 1 << 23


def _text_lines(path, label):
    """The file's lines (``.gz`` decompressed as it is read, with the cap of
    ``mcbat.statcast.files``; UTF-8 with or without a BOM; each line with its newline),
    or ``InputError`` naming the file, and the line and byte of a decoding error."""
    import codecs
    import gzip
    import zlib

    status = check_regular_file(path, label)
    try:
        raw = path.open("rb")
    except OSError as err:
        raise InputError(None, f"cannot read the file: {err.strerror or err}", label) from None
    with raw:
        gz = path.suffix.lower() == ".gz" or raw.peek(2)[:2] == b"\x1f\x8b"
        stream = CappedReader.for_file(gzip.GzipFile(fileobj=raw), status.st_size,
                                       label) if gz else raw
        decoder = codecs.getincrementaldecoder("utf-8-sig")()
        consumed, line, pending, pending_size = 0, 1, [], 0
        while True:
            try:
                block = stream.read(_BLOCK_BYTES)
            except (OSError, EOFError, zlib.error) as err:
                raise InputError(None, f"cannot read the file: {err}", label) from None
            try:
                text = decoder.decode(block, final=not block)
            except UnicodeDecodeError as err:
                at = line + block.count(b"\n", 0, max(err.start, 0))
                raise InputError(None, f"line {at}: not UTF-8 text (byte "
                                 f"{consumed + err.start}); a Savant export is a UTF-8 CSV "
                                 "file", label) from None
            consumed += len(block)
            pieces = text.split("\n")
            if len(pieces) > 1:
                pending.append(pieces[0])
                yield "".join(pending) + "\n"
                line += 1
                for piece in pieces[1:-1]:
                    yield piece + "\n"
                    line += 1
                pending, pending_size = [], 0
            pending.append(pieces[-1])
            pending_size += len(pieces[-1])
            if pending_size > MAX_LINE_BYTES:
                raise InputError(None, f"line {line}: longer than {MAX_LINE_BYTES:,} "
                                 "characters without a line break: not a CSV table", label)
            if not block:
                break
        tail = "".join(pending)
        if tail:
            yield tail


def _csv_chunks(path, label, rows=None):
    """The export's wanted columns as strings, ``rows`` rows at a time: yields
    ``(frame, lines, duplicates)``, ``lines`` the file line of each row.

    Every row is checked to have as many fields as the header (Python's csv module, in
    strict mode): pandas would pad a short row with NaN, and a download cut in the middle
    of a row would pass for a row of missing values. Blank lines are skipped.
    """
    import pandas as pd

    rows = CHUNK_ROWS if rows is None else rows
    reader = csv.reader(_text_lines(path, label), strict=True)
    try:
        header = next(reader, None)
        if not header or not any(cell.strip() for cell in header):
            raise InputError(None, "empty file: no header line (not a Savant export)",
                             label)
        names = [cell.strip() for cell in header]
        _check_required(names, label)
        first = {}
        for index, column in enumerate(names):
            first.setdefault(column, index)
        duplicates = sorted(c for c in first if names.count(c) > 1)
        wanted = sorted(first[c] for c in (*REQUIRED, *OPTIONAL) if c in first)
        columns = [names[i] for i in wanted]
        width = len(header)
        pick = operator.itemgetter(*wanted)
        marks = [(first[c], c) for c in ("pitch_type", "game_date", "game_pk")]
        body, lines = [], []
        emitted = False
        for row in reader:
            if not row:
                continue
            if len(row) != width:
                raise InputError(None, f"line {reader.line_num}: {len(row)} fields where "
                                 f"the header has {width}: the file is truncated or "
                                 "malformed (an interrupted download?)", label)
            if all(row[i].strip() == c for i, c in marks):
                raise InputError(None, f"line {reader.line_num}: the header line again "
                                 "(the column names as a row): two exports concatenated "
                                 "with their headers? Remove the line (and check for "
                                 "pitches given twice)", label)
            body.append(pick(row))
            lines.append(reader.line_num)
            if len(body) == rows:
                yield pd.DataFrame(body, columns=columns, dtype=object), np.array(lines), \
                    duplicates
                body, lines, emitted = [], [], True
    except csv.Error as err:
        raise InputError(None, f"line {reader.line_num}: malformed CSV ({err}): the file "
                         "is truncated or malformed (an interrupted download?)",
                         label) from None
    if body or not emitted:
        yield pd.DataFrame(body, columns=columns, dtype=object), np.array(lines, dtype=int), \
            duplicates


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
        num[column], bad = _numbers(raw[column], lines)
        if column in _IDENTIFIERS and bad:
            where = f"line {bad['line']}" if "line" in bad else f"row {bad['row']}"
            raise InputError(column, f"{where}: {bad['value']!r} is not an identifier (a "
                             "whole number)", label)
        if bad:
            report["non_numeric"][column] = bad
        if column in RANGES:
            far = _out_of_range(num[column], RANGES[column], lines)
            if far:
                report["out_of_range"][column] = far
    _check_identifiers({c: num[c] for c in _IDENTIFIERS}, label, lines)
    text = {c: _text(raw[c]) for c in _TEXT}

    speed, vertical, horizontal = kinematics.plate_crossing(
        num["vx0"], num["vy0"], num["vz0"], num["ax"], num["ay"], num["az"])
    game_date = _dates(raw["game_date"])
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
        **{c: _integers(num[c]) for c in _IDENTIFIERS},
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


def _numbers(values, lines):
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
                given[given] = ~stripped.isin(_MISSING_MARKERS).to_numpy()
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


def _out_of_range(values, bounds, lines):
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


def _check_identifiers(columns, label, lines):
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


def _integers(values):
    """Identifiers as nullable integers (NaN where missing or not a whole number)."""
    import pandas as pd

    whole = np.where(np.isfinite(values) & (values == np.round(values)), values, np.nan)
    return pd.array(whole, dtype="Int64")


def _text(values):
    """A text column as Python strings with NaN where missing (object dtype, so that
    ``df.pitch_type == "FF"`` is False, not NA, on a missing value)."""
    out = np.empty(len(values), dtype=object)
    for i, value in enumerate(values.tolist()):
        if value is None or (isinstance(value, float) and math.isnan(value)):
            out[i] = np.nan
            continue
        value = str(value).strip()
        out[i] = np.nan if value in _MISSING_MARKERS else value
    return out


def _dates(values):
    import pandas as pd

    return pd.to_datetime(values, errors="coerce", format="mixed").dt.normalize() \
        if len(values) else pd.Series([], dtype="datetime64[ns]")


def _tidy_from_parquet(table, path, label):
    """A table ``write`` wrote: its columns and the report kept in its metadata."""
    import pyarrow.parquet as pq

    missing = [c for c in COLUMNS if c not in table.columns and c not in _DERIVED]
    if missing:
        raise InputError(None, f"a tidy Statcast table but missing column"
                         f"{'s' if len(missing) > 1 else ''} {', '.join(missing)}", label)
    _check_identifiers({c: table[c] for c in _IDENTIFIERS}, label, None)
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


def summarize(df):
    """The counts ``mcbat statcast`` prints, as a JSON-ready dict.

    Keys: ``rows``, ``seasons`` (sorted), ``pitch_types`` (count per type, most common
    first; ``"(none)"`` for rows without one), ``balls_in_play``, ``with_distance``
    (``hit_distance_sc`` measured), ``with_bat_tracking`` (``bat_speed`` measured),
    ``with_launch`` (balls in play with launch speed and angle), ``plate`` (median and
    standard deviation of the plate speed and approach angles per pitch type),
    ``attack_direction_check`` (see ``docs/statcast.md``), ``units`` and the reader's
    report (``missing_columns``, ``non_numeric``, ``elevation_missing``,
    ``unknown_home_teams``, ``duplicate_columns``, ``duplicate_pitches``) and ``left_out``
    (rows the reader left out, by reason).
    """
    seasons = sorted({int(y) for y in df["game_year"].dropna()})
    types = df["pitch_type"].fillna("(none)").value_counts()
    bip = balls_in_play(df)
    launch = bip & df["launch_speed"].notna().to_numpy() & df["launch_angle"].notna().to_numpy()
    plate = {}
    for kind, rows in df.groupby(df["pitch_type"].fillna("(none)")):
        entry = {"pitches": int(len(rows))}
        for column in ("pitch_speed", "vertical_approach_angle",
                       "horizontal_approach_angle"):
            values = rows[column].dropna()
            entry[column] = ({"median": float(values.median()),
                              "sd": float(values.std(ddof=1)) if len(values) > 1 else None}
                             if len(values) else None)
        plate[str(kind)] = entry
    report = dict(df.attrs.get("statcast", {}))
    out = {
        "rows": int(len(df)),
        "seasons": seasons,
        "pitch_types": {str(k): int(v) for k, v in types.items()},
        "balls_in_play": int(bip.sum()),
        "with_launch": int(launch.sum()),
        "with_distance": int(df["hit_distance_sc"].notna().sum()),
        "with_bat_tracking": int(df["bat_speed"].notna().sum()),
        "plate": plate,
        "attack_direction_check": attack_direction_check(df),
        "units": dict(UNITS),
    }
    out["left_out"] = dict(report.get("left_out", {}))
    for key in ("source", "missing_columns", "non_numeric", "out_of_range",
                "elevation_missing", "unknown_home_teams", "duplicate_columns",
                "duplicate_pitches"):
        if key in report:
            out[key] = report[key]
    return out


def attack_direction_check(df, minimum=20):
    """Whether the swing's attack direction agrees in sign with where the ball went.

    Among balls in play with both an attack direction and a spray angle, the correlation
    between ``attack_direction`` and the spray angle towards the batter's opposite field
    (``spray_angle`` for a right-handed batter, ``-spray_angle`` for a left-handed one).
    A clearly positive value confirms the convention of ``docs/statcast.md`` (positive
    towards the opposite field) on the user's own data. None with fewer than ``minimum``
    such rows.
    """
    sign = np.where(df["handedness"].to_numpy() == "L", -1.0, 1.0)
    opposite = sign * df["spray_angle"].to_numpy(dtype=float)
    attack = df["attack_direction"].to_numpy(dtype=float)
    rows = balls_in_play(df) & np.isfinite(opposite) & np.isfinite(attack)
    if rows.sum() < minimum:
        return None
    r = float(np.corrcoef(attack[rows], opposite[rows])[0, 1])
    return {"rows": int(rows.sum()), "correlation": r}
