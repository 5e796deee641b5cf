"""Read the file of a study's ``[pitches]`` into plain numpy columns (:mod:`mcbat.study.pitches`).

The study layer may not read tables (it imports no pandas or pyarrow), so the runner reads
the file once per run (and once per Dask worker process), hashes its bytes, and hands the
columns to :meth:`mcbat.study.game.GameStudy.with_pitch_table`. Accepted files:

* mcbat's tidy table (one row per pitch, :data:`mcbat.study.pitches.TABLE_UNITS`), as
  Parquet or CSV: the columns are used as they are;
* a raw Baseball Savant CSV (``release_speed``, ``vx0`` ...): converted by
  :func:`mcbat.statcast.read` first.

With the swing drawn from the rows (``swing = true``), the rows Savant marks as bunts
(:func:`mcbat.statcast.is_bunt`) are flagged in the column :data:`BUNT_COLUMN`; the study
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
from mcbat.statcast.collision import is_bunt
from mcbat.study.pitches import BUNT_COLUMN, SWING_KEYS, PitchTable

__all__ = ["load_pitches", "read_pitch_table"]

#: Columns read as text (the others as numbers).
_TEXT = ("pitch_type", "p_throws", "handedness", "bb_type")
# The tidy table is told from a raw Savant export by its plate speed.
_TIDY_MARK = "pitch_speed"


def load_pitches(study):
    """``study`` with the rows of its ``[pitches]`` file loaded (the study itself when it
    has no ``[pitches]`` or has them already).

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
    needed = source.needed_columns(study.handedness is None)
    try:
        table = read_pitch_table(source.path, needed, source.file)
    except InputError as err:
        raise err.within(source=study.source) from None
    return study.with_pitch_table(table)


def read_pitch_table(path, needed, where=None) -> PitchTable:
    """The columns ``needed`` of the Statcast table at ``path`` as numpy arrays.

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
    try:
        with open(path, "rb") as handle:
            stamp = os.fstat(handle.fileno())
            data = handle.read()
    except OSError as err:
        reason = os.strerror(err.errno) if err.errno else str(err)
        raise InputError("pitches.file", f"cannot read {where}: {reason}") from None
    frame = _parse(data, where)
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
    for name in needed:
        column = frame[name]
        if name in _TEXT:
            columns[name] = column.astype(object).where(column.notna(), "").astype(str) \
                .to_numpy(object)
        else:
            columns[name] = _numbers(column, name, where)
    return PitchTable(columns, len(frame), hashlib.sha256(data).hexdigest(),
                      os.path.basename(str(path)))


def _parse(data: bytes, where: str) -> pd.DataFrame | None:
    """The tidy table in ``data`` (Parquet, told by its magic bytes, or CSV), or None for
    anything else (a raw Savant export: :func:`_from_savant`)."""
    if data[:4] == b"PAR1":
        import pyarrow as pa
        import pyarrow.parquet as pq

        try:
            table = pq.read_table(io.BytesIO(data))
        except (pa.ArrowException, OSError, ValueError) as err:
            raise InputError("pitches.file", f"{where}: not a readable Parquet file "
                             f"({_first_line(err)})") from None
        return table.to_pandas() if _TIDY_MARK in table.column_names else None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return None  # (the Savant reader says what is wrong with it)
    rows = csv.reader(io.StringIO(text), strict=True)
    try:
        header = [cell.strip() for cell in next(rows, [])]
        if _TIDY_MARK not in header:
            return None
        # Every row as wide as the header (pandas would pad a row cut short with NaN: a
        # truncated file would pass for missing values).
        for row in rows:
            if row and len(row) != len(header):
                raise InputError("pitches.file", f"{where}: line {rows.line_num}: "
                                 f"{len(row)} fields where the header has {len(header)}: "
                                 "the file is truncated or malformed")
    except csv.Error as err:
        raise InputError("pitches.file", f"{where}: line {rows.line_num}: malformed CSV "
                         f"({err}): the file is truncated or malformed") from None
    return pd.read_csv(io.StringIO(text), low_memory=False)


def _from_savant(path, where: str) -> pd.DataFrame:
    """A raw Savant export as the tidy table (:func:`mcbat.statcast.read`)."""
    from mcbat.statcast import read

    try:
        return read(path, name=where)
    except InputError as err:
        raise InputError("pitches.file", f"{where}: {err.message}") from None


def _numbers(column, name, where) -> np.ndarray:
    """A numeric column as float64 (missing: NaN). Text that is not a number is refused:
    it means the wrong column or a broken file, not a missing value."""
    values = pd.to_numeric(column, errors="coerce")
    bad = values.isna() & column.notna() & (column.astype(str).str.strip() != "")
    if bad.any():
        first = int(np.flatnonzero(bad.to_numpy())[0])
        raise InputError("pitches.file", f"{where}: column {name} holds "
                         f"{str(column.iloc[first])[:40]!r} (row {first}), not a number")
    return values.to_numpy(np.float64, na_value=np.nan)


def _first_line(err) -> str:
    text = str(err).strip().splitlines()
    return text[0][:200] if text else type(err).__name__

