"""Reading a dataset directory back: ``load``."""

from __future__ import annotations

import warnings

import pyarrow as pa
import pyarrow.parquet as pq

from mcbat.core import status as st
from mcbat.dataset import storage
from mcbat.dataset.check import UNVERIFIED, check_dataset
from mcbat.dataset.chunks import checksum, chunk_name
from mcbat.dataset.schema import MEASURED_SUFFIX, UNITS
from mcbat.errors import InputError

__all__ = ["load", "units_of"]


def units_of(columns) -> dict:
    """``{column: unit}`` for the given column names (``"1"`` for dimensionless; a
    ``*_measured`` column has the unit of its model column)."""
    units = {}
    for name in columns:
        base = name[:-len(MEASURED_SUFFIX)] if name.endswith(MEASURED_SUFFIX) else name
        if name in UNITS or base in UNITS:
            units[name] = UNITS.get(name, UNITS.get(base))
    return units


def load(directory, columns=None, labels=False, allow_partial=False):
    """Load a dataset directory written by ``mcbat run`` as a pandas DataFrame.

    Parameters
    ----------
    directory : str or Path
        The dataset directory, or its URL (see ``mcbat.dataset.storage``).
    columns : list of str, optional
        Only these columns.
    labels : bool
        Turn ``status`` and ``end_state`` codes into categorical labels.
    allow_partial : bool
        Read the chunks that belong to the dataset even if some are missing or do not
        match the manifest, with a warning that says what is left out. By default such a
        dataset is refused (``mcbat.dataset.check.check_dataset``). Every file's bytes
        are checked against the CRC-32 the manifest recorded as they are read (~1 GB/s):
        a corrupted chunk is never returned. A manifest of an older mcbat that records no
        checksums is read with a warning that the bytes are unverified.

    Returns
    -------
    pandas.DataFrame
        Rows sorted by ``sample_id``. ``df.attrs["units"]`` maps every column to its unit,
        ``df.attrs["mcbat"]`` holds the dataset manifest and ``df.attrs["directory"]``
        the directory.

    Raises
    ------
    InputError
        No such directory, not an mcbat dataset, an incomplete or inconsistent dataset
        (unless ``allow_partial``), no chunk files yet, or an unknown column.
    """
    import pandas as pd

    unknown = sorted(set(columns or ()) - set(UNITS))
    if unknown:
        raise InputError("columns", f"unknown column {unknown[0]!r}")
    check = check_dataset(directory)
    directory, manifest = check.directory, check.manifest
    if not check.ok:
        if not allow_partial:
            raise InputError(None, f"{check.problems()[0]} ({{allow_partial}} reads what is "
                             "there; `mcbat check` lists every problem)", str(directory),
                             mentions={"allow_partial": True})
        warnings.warn(f"{directory}: partial dataset: " + "; ".join(check.problems()),
                      stacklevel=2)
    if check.unverified:
        warnings.warn(f"{directory}: {UNVERIFIED}", stacklevel=2)
    records = manifest.get("files") or {}
    tables = []
    for k, path in sorted(check.good.items()):
        name = chunk_name(k)
        try:
            tables.append(_read_chunk(path, records.get(name), columns, directory))
        except InputError:
            raise
        except (OSError, ValueError, pa.ArrowException) as err:
            if not allow_partial:
                raise InputError(None, f"{name}: {err}; rerun `mcbat run` to recompute it "
                                 "({allow_partial} reads the other chunks)", str(directory),
                                 mentions={"allow_partial": True}) from None
            warnings.warn(f"{directory}: {name} left out: {err}", stacklevel=2)
    if not tables:
        if check.summary_only:
            raise InputError(None, "a summary-only run stores no rows: read its binned "
                             "statistics with mcbat.load_summary(DIR), or rerun without "
                             "--summary-only to store the rows too", str(directory))
        raise InputError(None, "the dataset has no complete chunk files yet", str(directory))
    table = pa.concat_tables(tables)
    df = table.to_pandas()
    if "sample_id" in df.columns:
        df = df.sort_values("sample_id", kind="stable").reset_index(drop=True)
    if labels:
        if "status" in df.columns:
            df["status"] = pd.Categorical.from_codes(df["status"].astype(int),
                                                     list(st.STATUS_NAMES.values()))
        if "end_state" in df.columns:
            df["end_state"] = pd.Categorical.from_codes(df["end_state"].astype(int),
                                                        list(st.END_STATE_NAMES.values()))
    df.attrs["units"] = units_of(df.columns)
    df.attrs["mcbat"] = manifest
    df.attrs["directory"] = str(directory)
    return df


def _read_chunk(path, record, columns, directory):
    """One chunk file's table (``columns``), its bytes checked against the CRC-32 of its
    manifest ``record`` (None: unverified); ValueError if they do not match."""
    data = storage.read_bytes(path)
    if record is not None and checksum(data) != record.get("crc32"):
        raise ValueError("checksum mismatch (the file was changed or corrupted)")
    # One file already in memory: Parquet's file reader, not read_table's dataset scanner
    # (whose background tasks have been seen to abort a process at exit: "terminate
    # called without an active exception", apache/arrow#34314).
    parquet = pq.ParquetFile(pa.BufferReader(data))
    absent = [c for c in columns or () if c not in parquet.schema_arrow.names]
    if absent:
        raise InputError("columns", f"{absent[0]!r} is not stored in this dataset (its "
                         "study's [output] columns leave it out)", str(directory))
    return parquet.read(columns=columns)
