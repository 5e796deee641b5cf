"""Reading a dataset directory back: :func:`load`."""

from __future__ import annotations

import pyarrow as pa

from mcbat.core import status as st
from mcbat.dataset import storage
from mcbat.dataset.chunks import MANIFEST, chunk_files, read_manifest, read_table
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


def load(directory, columns=None, labels=False):
    """Load a dataset directory written by ``mcbat run`` as a pandas DataFrame.

    Parameters
    ----------
    directory : str or Path
        The dataset directory, or its URL (see :mod:`mcbat.dataset.storage`).
    columns : list of str, optional
        Only these columns.
    labels : bool
        Turn ``status`` and ``end_state`` codes into categorical labels.

    Returns
    -------
    pandas.DataFrame
        Rows sorted by ``sample_id``. ``df.attrs["units"]`` maps every column to its unit,
        ``df.attrs["mcbat"]`` holds the dataset manifest and ``df.attrs["directory"]``
        the directory.

    Raises
    ------
    InputError
        No such directory, not an mcbat dataset, no chunk files yet, or an unknown column.
    """
    import pandas as pd

    directory = storage.location(directory)
    if storage.entry_type(directory) != "dir":
        raise InputError(None, "no such dataset directory", str(directory))
    manifest = read_manifest(directory)
    if manifest is None:
        raise InputError(None, f"not an mcbat dataset (no {MANIFEST})", str(directory))
    files = [path for _, path in sorted(chunk_files(directory).items())]
    if not files:
        raise InputError(None, "the dataset has no chunk files yet", str(directory))
    unknown = sorted(set(columns or ()) - set(UNITS))
    if unknown:
        raise InputError("columns", f"unknown column {unknown[0]!r}")
    table = pa.concat_tables(read_table(path, columns) for path in files)
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
