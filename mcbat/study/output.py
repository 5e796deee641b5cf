"""What a run stores: the ``[output]`` and ``[summary]`` sections of a study.

``[output]`` chooses the columns of the chunk files and their precision::

    [output]
    columns = ["exit_speed", "scattering_angle", "from_barrel_end"]  # + sample_id, always
    precision = "float32"      # outputs only; inputs stay float64 (default "float64")
    compression = "lz4"        # of float columns: "none" (default), "lz4", "zstd", "snappy"

The inputs of a row are always enough to re-solve it: with a column selection they are the
study and ``sample_id`` (the samples are drawn from ``(seed, sample_id)``), so a selection
may drop them. float32 applies to outputs and derived columns only (7 significant digits);
inputs, ``sample_id`` and status codes keep their types. Floats are stored uncompressed by
default: doubles of physics barely compress (LZ4 saves ~12 % of a chunk for 2-3 times the
writing time, measured on ``studies/throughput.toml``); integer columns always use LZ4.

``[summary]`` asks for binned statistics instead of (or besides) the rows::

    [summary]
    by = { from_barrel_end = { bins = 40, low = 0, high = 40, unit = "cm" } }
    columns = ["exit_speed", "scattering_angle"]
    quantiles = [0.05, 0.5, 0.95]
    share_above = { exit_speed = [30, 40] }   # the share of rows with exit_speed > 30 m/s...

``by`` names up to three columns of the dataset, each with a regular grid of ``bins`` over
``[low, high)`` in ``unit`` (default: the column's own unit). ``share_above`` gives, for
columns among ``columns``, one threshold or a list of them in the column's stored unit:
each bin gets the share of the column's values strictly above it. Column names are checked
against the dataset's schema by the runner (``mcbat.runner.plan``), which knows it.
"""

from __future__ import annotations

from dataclasses import dataclass

from mcbat.checks import check_keys, integer, number
from mcbat.errors import InputError
from mcbat.study import units as u

__all__ = ["COMPRESSIONS", "MAX_BY", "MAX_SHARES", "MAX_SUMMARY_BINS", "PRECISIONS",
           "OutputSpec", "SummaryAxis", "SummarySpec", "parse_columns", "parse_output",
           "parse_summary"]

PRECISIONS = ("float64", "float32")
COMPRESSIONS = ("none", "lz4", "zstd", "snappy")
#: At most this many ``by`` columns, and bins in all (their product).
MAX_BY = 3
MAX_SUMMARY_BINS = 100_000
#: At most this many ``share_above`` thresholds in all.
MAX_SHARES = 64


@dataclass(frozen=True)
class OutputSpec:
    """The ``[output]`` section: ``columns`` (None: all), ``precision`` of the outputs,
    ``compression`` of the float columns."""

    columns: tuple | None = None
    precision: str = "float64"
    compression: str = "none"

    def config(self) -> dict:
        """JSON-serialisable form (part of the dataset's config hash)."""
        return {"columns": None if self.columns is None else list(self.columns),
                "precision": self.precision, "compression": self.compression}


@dataclass(frozen=True)
class SummaryAxis:
    """One ``by`` column: ``bins`` regular bins over ``[low, high)``.

    ``low`` and ``high`` are in the column's stored unit (``column_unit``);
    ``unit``, ``low_given`` and ``high_given`` are what the study wrote (the summary's
    bin-edge columns use them).
    """

    name: str
    bins: int
    low: float
    high: float
    unit: str
    low_given: float
    high_given: float

    def config(self) -> dict:
        """JSON-serialisable form."""
        return {"name": self.name, "bins": self.bins, "low": self.low_given,
                "high": self.high_given, "unit": self.unit}


@dataclass(frozen=True)
class SummarySpec:
    """The ``[summary]`` section: the ``by`` axes, the summarised ``columns``, the
    ``quantiles`` (probabilities in (0, 1)) and the ``share_above`` thresholds (pairs
    ``(column, threshold)``, the threshold in the column's stored unit, in the order given).
    """

    by: tuple
    columns: tuple
    quantiles: tuple = ()
    share_above: tuple = ()

    @property
    def n_bins(self) -> int:
        """Bins in all (the product over the axes)."""
        total = 1
        for axis in self.by:
            total *= axis.bins
        return total

    def config(self) -> dict:
        """JSON-serialisable form."""
        config = {"by": [axis.config() for axis in self.by], "columns": list(self.columns),
                  "quantiles": list(self.quantiles)}
        if self.share_above:  # (only when given: the config hash of other studies stays)
            config["share_above"] = [[name, t] for name, t in self.share_above]
        return config


def parse_columns(value, field) -> tuple:
    """A non-empty list of distinct column names (strings)."""
    if isinstance(value, str):
        value = [name.strip() for name in value.split(",") if name.strip()]
    if not isinstance(value, list) or not value:
        raise InputError(field, f"must be a non-empty list of column names, got {value!r}")
    for i, name in enumerate(value):
        if not isinstance(name, str) or not name:
            raise InputError(f"{field}[{i}]", f"must be a column name, got {name!r}")
    for name in value:
        if value.count(name) > 1:
            raise InputError(field, f"names {name!r} twice")
    return tuple(value)


def _choice(value, field, allowed):
    if value not in allowed:
        raise InputError(field, f"must be one of {', '.join(map(repr, allowed))}, "
                         f"got {value!r}")
    return value


def parse_output(table) -> OutputSpec:
    """The ``[output]`` section (empty: every column, float64)."""
    table = check_keys(table, "output", (), ("columns", "precision", "compression"))
    columns = (None if "columns" not in table
               else parse_columns(table["columns"], "output.columns"))
    return OutputSpec(columns,
                      _choice(table.get("precision", "float64"), "output.precision",
                              PRECISIONS),
                      _choice(table.get("compression", "none"), "output.compression",
                              COMPRESSIONS))


def _axis(name, spec, field, column_unit) -> SummaryAxis:
    spec = check_keys(spec, field, ("bins", "low", "high"), ("unit",))
    bins = integer(spec["bins"], f"{field}.bins", minimum=1, maximum=MAX_SUMMARY_BINS)
    low, high = number(spec["low"], f"{field}.low"), number(spec["high"], f"{field}.high")
    if not high > low:
        raise InputError(f"{field}.high", f"must be > low ({low!r}), got {high!r}")
    unit = spec.get("unit", column_unit)
    if "unit" in spec and not isinstance(unit, str):
        raise InputError(f"{field}.unit", f"must be a string, got {unit!r}")
    if column_unit is None:  # the runner checks the name; keep the values as given
        return SummaryAxis(name, bins, low, high, unit, low, high)
    return SummaryAxis(name, bins, convert(low, unit, column_unit, f"{field}.unit"),
                       convert(high, unit, column_unit, f"{field}.unit"), unit, low, high)


def convert(value, unit, column_unit, field) -> float:
    """``value`` in ``unit`` expressed in ``column_unit`` (a unit of the same quantity,
    ``mcbat.study.units.UNITS``; a unit outside that table must be the column's own)."""
    if unit == column_unit:
        return float(value)
    for quantity, units in u.UNITS.items():
        if column_unit in units:
            if unit not in units:
                raise InputError(field, f"{unit!r} is not a unit of this column's quantity "
                                 f"({quantity}; the column is in {column_unit}): use one of "
                                 f"{', '.join(units)}")
            return float(u.to_si(value, unit, quantity, field)) / units[column_unit]
    raise InputError(field, f"the column is in {column_unit!r}: give its bounds in that unit, "
                     f"got {unit!r}")


def parse_summary(table, column_units=None) -> SummarySpec:
    """The ``[summary]`` section.

    Parameters
    ----------
    table : dict
        The section, as ``tomllib`` returns it.
    column_units : dict, optional
        ``{column: stored unit}`` of the dataset: names are checked against it and the
        ``by`` bounds converted to the stored units. Without it only the form is checked.
    """
    table = check_keys(table, "summary", ("by", "columns"), ("quantiles", "share_above"))
    by = table["by"]
    if not isinstance(by, dict):
        raise InputError("summary.by", f"must be a table of columns, like "
                         f"{{ from_barrel_end = {{ bins = 40, low = 0, high = 40, unit = "
                         f"\"cm\" }} }}, got {by!r}")
    if not by or len(by) > MAX_BY:
        raise InputError("summary.by", f"must name 1 to {MAX_BY} columns, got {len(by)}")
    axes = []
    for name, spec in by.items():
        field = f"summary.by.{name}"
        unit = None
        if column_units is not None:
            if name not in column_units:
                raise InputError(field, "not a column of this study's dataset")
            unit = column_units[name]
        axes.append(_axis(name, spec, field, unit))
    columns = parse_columns(table["columns"], "summary.columns")
    if column_units is not None:
        for i, name in enumerate(columns):
            if name not in column_units:
                raise InputError(f"summary.columns[{i}]",
                                 f"{name!r} is not a column of this study's dataset")
    quantiles = table.get("quantiles", [])
    if not isinstance(quantiles, list):
        raise InputError("summary.quantiles", f"must be a list of probabilities, got "
                         f"{quantiles!r}")
    probs = []
    for i, q in enumerate(quantiles):
        q = number(q, f"summary.quantiles[{i}]")
        if not 0.0 < q < 1.0:
            raise InputError(f"summary.quantiles[{i}]", f"must be in (0, 1), got {q!r}")
        probs.append(q)
    shares = _share_above(table.get("share_above", {}), columns)
    spec = SummarySpec(tuple(axes), columns, tuple(sorted(set(probs))), shares)
    if spec.n_bins > MAX_SUMMARY_BINS:
        raise InputError("summary.by", f"{spec.n_bins:,} bins in all; at most "
                         f"{MAX_SUMMARY_BINS:,}")
    return spec


def _share_above(table, columns) -> tuple:
    """``share_above``: ``{column = threshold}`` or ``{column = [thresholds]}``, each column
    one of ``columns``; pairs ``(column, threshold)``, each pair once."""
    if not isinstance(table, dict):
        raise InputError("summary.share_above", f"must be a table of columns and thresholds, "
                         f"like {{ hit_distance = 380 }}, got {table!r}")
    pairs = []
    for name, values in table.items():
        field = f"summary.share_above.{name}"
        if name not in columns:
            raise InputError(field, "must be one of summary.columns (its count of values is "
                             "the share's denominator)")
        if not isinstance(values, list):
            values = [values]
        if not values:
            raise InputError(field, "must be a threshold or a non-empty list of them")
        for i, value in enumerate(values):
            value = number(value, field if len(values) == 1 else f"{field}[{i}]")
            if (name, value) not in pairs:
                pairs.append((name, value))
    if len(pairs) > MAX_SHARES:
        raise InputError("summary.share_above", f"{len(pairs)} thresholds; at most "
                         f"{MAX_SHARES}")
    return tuple(pairs)
