"""Read the file of a study's ``[pitches]`` into plain numpy columns (``mcbat.study.pitches``).

The study layer may not read tables (it imports no pandas or pyarrow), so the runner reads
the file once per run (and once per Dask worker process), hashes its bytes, and hands the
columns to ``mcbat.study.game.GameStudy.with_pitch_table``. Accepted files:

* mcbat's tidy table (one row per pitch, ``mcbat.study.pitches.TABLE_UNITS``), as
  Parquet or CSV: the columns are used as they are;
* a raw Baseball Savant CSV (``release_speed``, ``vx0`` ...): converted by
  ``mcbat.statcast.read`` first.

With the swing drawn from the rows (``swing = true``), the rows Savant marks as bunts
(``mcbat.statcast.is_bunt``) are flagged in the column ``BUNT_COLUMN``; the study
leaves them out and counts them.

The bytes hashed are the bytes parsed (the file is read once), so the content hash in the
study's config is that of the rows drawn.
"""

from __future__ import annotations

import csv
import hashlib
import io
import os

import numpy as np
import pandas as pd

from mcbat.errors import InputError
from mcbat.runner.player_levels import OBSERVED, with_player_levels
from mcbat.statcast.collision import is_bunt
from mcbat.statcast.files import check_regular_file
from mcbat.study.pitches import BUNT_COLUMN, DUPLICATE_COLUMN, IDENTIFIERS, SWING_KEYS, PitchTable

__all__ = ["load_pitches", "read_pitch_table"]

#: Columns read as text (the others as numbers).
_TEXT = ("pitch_type", "p_throws", "handedness", "bb_type")
#: Cells that are a missing value (pandas writes NaN and <NA>, Savant null).
_MISSING = ("", "nan", "NaN", "NA", "<NA>", "null", "NULL", "None")
# The tidy table is told from a raw Savant export by its plate speed.
_TIDY_MARK = "pitch_speed"


def load_pitches(study, player_levels=True):
    """``study`` with the rows of its ``[pitches]`` file loaded (the study itself when it
    has no ``[pitches]`` or has them already), and with ``[pitches.player_levels]`` each
    row's players' contact estimated from their other games
    (``mcbat.runner.player_levels``; ``player_levels=False``: the league's contact for
    every row, as a fit of that contact needs).

    Raises
    ------
    InputError
        On ``pitches.file``, naming the study file: a file that cannot be read or parsed,
        or lacks a column the study needs; on ``pitches.<filter>`` when a filter selects
        no row.
    """
    source = getattr(study, "pitches", None)
    if source is None or study.pitch_rows is not None:
        return study
    needed = source.needed_columns(study.handedness is None,
                                   getattr(study, "location_columns", ()))
    # (the measured outcomes serve only the players' levels; a file without them gives
    # every row the league's contact)
    needed = tuple(c for c in needed if c not in OBSERVED)
    optional = OBSERVED if player_levels and source.player_levels is not None else ()
    try:
        table = read_pitch_table(source.path, needed, source.file, optional)
    except InputError as err:
        raise err.within(source=study.source) from None
    loaded = study.with_pitch_table(table)
    if not player_levels:
        return loaded
    try:
        return with_player_levels(loaded)
    except InputError as err:
        raise err.within(source=study.source) from None


def read_pitch_table(path, needed, where=None, optional=()) -> PitchTable:
    """The columns ``needed`` (and those of ``optional`` the table has) of the Statcast
    table at ``path`` as numpy arrays.

    Parameters
    ----------
    path : str or Path
        A tidy table (``.parquet``, or CSV) or a Savant CSV.
    needed : sequence of str
        Tidy column names.
    where : str, optional
        The file as the user wrote it (messages name it); default ``path``.

    Raises
    ------
    InputError
        On ``pitches.file``: unreadable, not a table, or a needed column missing.
    """
    where = str(path) if where is None else where
    # a device (/dev/zero) would never end, a FIFO would block: refused before opening
    try:
        if os.path.exists(path):  # (a missing file: the open below says so)
            check_regular_file(path, where, "pitches.file")
    except InputError as err:
        raise InputError("pitches.file", f"cannot read {where}: {err.message}") from None
    try:
        with open(path, "rb") as handle:
            stamp = os.fstat(handle.fileno())
            data = handle.read()
    except OSError as err:
        reason = os.strerror(err.errno) if err.errno else str(err)
        raise InputError("pitches.file", f"cannot read {where}: {reason}") from None
    frame, lines = _parse(data, where)
    if frame is None:
        # A raw export: the Savant reader converts it, from the file itself (its CSV
        # checks report line numbers), which must still hold the bytes hashed above.
        frame = _from_savant(path, where)
        try:
            now = os.stat(path)
        except OSError:
            now = None
        if now is None or (now.st_size, now.st_mtime_ns) != (stamp.st_size,
                                                               stamp.st_mtime_ns):
            raise InputError("pitches.file", f"{where} changed while it was read; rerun")
    if lines is None:  # Parquet, or rows the Savant reader renumbered: rows from 1
        lines = np.arange(1, len(frame) + 1)
        unit = "row"
    else:
        unit = "line"
    missing = [name for name in needed if name not in frame.columns]
    if missing:
        raise InputError("pitches.file", f"{where} has no column {', '.join(missing)} "
                         f"(needed: {', '.join(needed)}); expected mcbat's tidy Statcast "
                         "table or a Baseball Savant CSV")
    columns = {}
    swing = [c for c in SWING_KEYS.values() if c in needed]
    if swing:
        # a bunt is no swing the game model draws: the study leaves such rows out and
        # counts them ("bunts"), whatever their swing values
        text = {c: frame[c].to_numpy(object) if c in frame.columns else None
                for c in ("description", "events", "des")}
        columns[BUNT_COLUMN] = (is_bunt(**text).astype(np.float64)
                                if any(v is not None for v in text.values())
                                else np.zeros(len(frame)))
    for name in (*needed, *(c for c in optional if c in frame.columns)):
        column = frame[name]
        if name in _TEXT:
            given = column.notna() & ~column.astype(str).str.strip().isin(_MISSING)
            columns[name] = column.astype(object).where(given, "").astype(str) \
                .to_numpy(object)
        else:
            columns[name] = _numbers(column, name, where, lines, unit)
        if name in IDENTIFIERS:
            _check_identifier(columns[name], name, where, lines, unit)
    columns[DUPLICATE_COLUMN] = _repeated(frame)
    return PitchTable(columns, len(frame), hashlib.sha256(data).hexdigest(),
                      os.path.basename(str(path)))


def _parse(data: bytes, where: str) -> pd.DataFrame | None:
    """The tidy table in ``data`` (Parquet, told by its magic bytes, or CSV), or None for
    anything else (a raw Savant export: ``_from_savant``)."""
    if data[:4] == b"PAR1":
        import pyarrow as pa
        import pyarrow.parquet as pq

        try:
            # the file reader, not read_table's dataset scanner (mcbat.dataset.chunks.read_table)
            table = pq.ParquetFile(pa.BufferReader(data)).read()
        except (pa.ArrowException, OSError, ValueError) as err:
            raise InputError("pitches.file", f"{where}: not a readable Parquet file "
                             f"({_first_line(err)})") from None
        return (table.to_pandas(), None) if _TIDY_MARK in table.column_names else (None, None)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return None, None  # (the Savant reader says what is wrong with it)
    rows = csv.reader(io.StringIO(text), strict=True)
    lines = []
    try:
        header = [cell.strip() for cell in next(rows, [])]
        if _TIDY_MARK not in header:
            return None, None
        # Every row as wide as the header (pandas would pad a row cut short with NaN: a
        # truncated file would pass for missing values).
        for row in rows:
            if not row:
                continue
            if len(row) != len(header):
                raise InputError("pitches.file", f"{where}: line {rows.line_num}: "
                                 f"{len(row)} fields where the header has {len(header)}: "
                                 "the file is truncated or malformed")
            if [cell.strip() for cell in row] == header:
                raise InputError("pitches.file", f"{where}: line {rows.line_num}: the "
                                 "header line again (two tables concatenated?); remove it")
            lines.append(rows.line_num)
    except csv.Error as err:
        raise InputError("pitches.file", f"{where}: line {rows.line_num}: malformed CSV "
                         f"({err}): the file is truncated or malformed") from None
    frame = pd.read_csv(io.StringIO(text), low_memory=False, skip_blank_lines=True,
                        dtype=object, keep_default_na=False, na_values=[""])
    return frame, (np.asarray(lines) if len(lines) == len(frame) else None)


def _from_savant(path, where: str) -> pd.DataFrame:
    """A raw Savant export as the tidy table (``mcbat.statcast.read``)."""
    from mcbat.statcast import read

    try:
        return read(path, name=where, keep_duplicates=True)
    except InputError as err:
        field = f"column {err.field}: " if err.field else ""
        raise InputError("pitches.file", f"{where}: {field}{err.message}") from None


def _numbers(column, name, where, lines, unit) -> np.ndarray:
    """A numeric column as float64 (missing: NaN). Text that is not a number, or a bool,
    is refused: it means the wrong column or a broken file, not a missing value."""
    if pd.api.types.is_bool_dtype(column):
        raise InputError("pitches.file", f"{where}: column {name} holds true/false, not "
                         "numbers")
    text = column.astype(str).str.strip()
    values = pd.to_numeric(column.where(~text.isin(_MISSING), None), errors="coerce")
    bad = values.isna() & column.notna() & ~text.isin(_MISSING)
    if bad.any():
        first = int(np.flatnonzero(bad.to_numpy())[0])
        raise InputError("pitches.file", f"{where}: {unit} {int(lines[first])}: column "
                         f"{name} holds {str(column.iloc[first])[:40]!r}, not a number")
    out = values.to_numpy(np.float64, na_value=np.nan)
    if np.isinf(out).any():
        first = int(np.flatnonzero(np.isinf(out))[0])
        raise InputError("pitches.file", f"{where}: {unit} {int(lines[first])}: column "
                         f"{name} holds {str(column.iloc[first])[:40]!r}, not a finite "
                         "number")
    return out


#: Identifiers are whole numbers from 0 to 2**53 (exact in float64; MLBAM ids are below
#: 10**7).
MAX_IDENTIFIER = 2**53


def _check_identifier(values, name, where, lines, unit) -> None:
    """``InputError`` naming the line (or row) of the first identifier that is not a
    whole number in 0..2**53 (a missing one is allowed: the study leaves its row out)."""
    given = np.isfinite(values)
    with np.errstate(invalid="ignore"):
        bad = given & ~((values >= 0) & (values <= MAX_IDENTIFIER)
                        & (values == np.round(values)))
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        value = values[first]
        shown = f"{int(value)}" if value == np.round(value) and abs(value) < 1e21 else \
            f"{value:.17g}"
        raise InputError("pitches.file", f"{where}: {unit} {int(lines[first])}: column "
                         f"{name} holds {shown}, not an identifier (a whole number from 0 "
                         "to 2**53)")


def _repeated(frame) -> np.ndarray:
    """1.0 for each row whose ``game_pk``, ``at_bat_number`` and ``pitch_number`` repeat
    an earlier row's (all three given), else 0.0."""
    key = ["game_pk", "at_bat_number", "pitch_number"]
    out = np.zeros(len(frame))
    if not all(c in frame.columns for c in key):
        return out
    ids = frame[key].apply(pd.to_numeric, errors="coerce")
    known = ids.notna().all(axis=1).to_numpy()
    if known.any():
        out[known] = ids[known].duplicated(keep="first").to_numpy(np.float64)
    return out


def _first_line(err) -> str:
    text = str(err).strip().splitlines()
    return text[0][:200] if text else type(err).__name__

