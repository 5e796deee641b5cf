"""Write a result table as CSV or Parquet, by the file's suffix, with its units.

A table a command writes (``--out x.csv`` or ``--out x.parquet``) carries the unit of each
column: in a Parquet file, in the schema metadata (key ``mcbat``, JSON ``{"units": ...}``);
in a CSV file, in the column header itself, ``launch_speed [mph]``, so that a spreadsheet
or ``pandas.read_csv`` shows it and ``read_table`` gives the plain names back. The file
appears whole or not at all (``mcbat.dataset.storage.write_atomic``).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from mcbat.dataset import storage
from mcbat.errors import InputError

__all__ = ["TABLE_SUFFIXES", "read_table", "write_table"]

#: Suffixes a table can be written to.
TABLE_SUFFIXES = (".csv", ".parquet")
_UNIT = re.compile(r"^(.*) \[(.+)\]$")


def _suffix(path, field):
    suffix = Path(str(path)).suffix.lower()
    if suffix not in TABLE_SUFFIXES:
        raise InputError(field, f"must end in .csv or .parquet, got {str(path)!r}")
    return suffix


def write_table(df, path, units=None, *, field="out") -> Path:
    """Write ``df`` to ``path`` (``.csv`` or ``.parquet``) with the ``units`` of its
    columns (default ``df.attrs["units"]``); returns the path.

    Raises
    ------
    InputError
        Naming ``field`` when the suffix is neither.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(str(path))
    suffix = _suffix(path, field)
    units = dict(df.attrs.get("units", {}) if units is None else units)
    if suffix == ".csv":
        named = df.rename(columns={c: f"{c} [{units[c]}]" for c in df.columns
                                   if units.get(c) not in (None, "", "1", "code", "text",
                                                           "id")})
        storage.write_atomic(path, lambda fs, tmp: named.to_csv(tmp, index=False))
        return path
    table = pa.Table.from_pandas(df, preserve_index=False)
    meta = dict(table.schema.metadata or {})
    meta[b"mcbat"] = json.dumps({"units": {c: u for c, u in units.items()
                                           if c in df.columns}}).encode()
    table = table.replace_schema_metadata(meta)
    storage.write_atomic(path, lambda fs, tmp: pq.write_table(table, tmp, filesystem=fs))
    return path


def read_table(path):
    """A table ``write_table`` wrote, its plain column names and ``attrs["units"]``."""
    import pandas as pd
    import pyarrow.parquet as pq

    path = Path(str(path))
    if _suffix(path, "path") == ".csv":
        df = pd.read_csv(path)
        units, names = {}, {}
        for column in df.columns:
            found = _UNIT.match(str(column))
            if found:
                names[column] = found.group(1)
                units[found.group(1)] = found.group(2)
        df = df.rename(columns=names)
    else:
        df = pd.read_parquet(path)
        meta = pq.read_schema(path).metadata or {}
        units = json.loads(meta[b"mcbat"]).get("units", {}) if b"mcbat" in meta else {}
    df.attrs["units"] = units
    return df
