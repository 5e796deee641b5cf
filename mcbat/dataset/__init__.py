"""Parquet datasets of impacts.

``schema``
    The column contract: names, units, order, and ``mcbat.solving.derived.derive``,
    the one function that computes the derived columns.
``storage``
    Locations (local paths, URLs) and atomic writes.
``chunks``
    Chunk files and the manifest of a dataset directory.
``load``
    ``load``: a dataset directory as a pandas DataFrame (units in ``df.attrs``).
"""

from mcbat.dataset.load import load
from mcbat.dataset.schema import COLUMNS, SCHEMA_VERSION, UNITS

__all__ = ["COLUMNS", "SCHEMA_VERSION", "UNITS", "load"]
