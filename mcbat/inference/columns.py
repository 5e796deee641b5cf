"""The measured table an inference reads: its columns, their units and ranges, each
column read and checked (naming the column and the row); the result's columns."""

from __future__ import annotations

import numpy as np

from mcbat.core.contact_inference import INFERENCE_STATUS_NAMES
from mcbat.errors import InputError

__all__ = ["INPUT_COLUMNS", "OPTIONAL_COLUMNS", "OUTPUT_UNITS", "RANGES", "STATUS_NAMES",
           "check_range", "numeric_column", "read_column"]

INPUT_COLUMNS = {
    "pitch_speed": "mph", "vertical_approach_angle": "deg",
    "horizontal_approach_angle": "deg", "spin_rate": "rpm", "handedness": "R/L",
    "launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
}
"""Required columns (Statcast's tidy names, ``mcbat.statcast.read``) and their units: the
pitch at the plate (speed, approach angles: vertical < 0 descending, horizontal > 0
moving towards first base; spin rate), the batter's side, and the batted ball."""

OPTIONAL_COLUMNS = {"spin_axis": "deg", "bat_speed": "mph", "attack_angle": "deg",
                    "attack_direction": "deg"}
"""Optional columns. ``spin_axis`` (Statcast's clock-face convention, 180 = pure
backspin; NaN or absent: :attr:`SpinAssumptions.spin_axis`); ``bat_speed`` (where
finite, used, and the contact position inferred instead); ``attack_angle`` (where
finite, used instead of :attr:`SpinAssumptions.attack_angle`); ``attack_direction`` is
accepted but not used: it is one of the unknowns that reproduce the spray angle
(``docs/spin_inference.md``)."""

STATUS_NAMES = (*INFERENCE_STATUS_NAMES.values(), "missing_input")
"""Values of the ``inference_status`` column: ``missing_input`` for a row with a NaN in
a required column (with ``missing="flag"``)."""

OUTPUT_UNITS = {
    "inference_status": "", "inferred": "", "backspin": "rpm", "sidespin": "rpm",
    "gyrospin": "rpm", "spin_rate": "rpm", "undercut": "m", "bat_speed": "mph",
    "from_barrel_end": "m", "attack_direction": "deg", "attack_angle": "deg",
    "collision_efficiency": "1", "inference_iterations": "", "kernel_evaluations": "",
}
"""Columns of :func:`infer_spin`'s result and their units."""


def read_column(table, name, n, required=True):
    """A column as an array (None if optional and absent)."""
    if name not in table:
        if required:
            raise InputError(name, "missing column (infer_spin needs: "
                             f"{', '.join(INPUT_COLUMNS)})")
        return None
    values = np.asarray(table[name])
    if values.shape != (n,):
        raise InputError(name, f"must be a 1-D column of {n} values, got shape "
                         f"{values.shape}")
    return values


def numeric_column(table, name, n, required=True):
    """A column as float64 (None if optional and absent): finite values or NaN."""
    values = read_column(table, name, n, required)
    if values is None:
        return None
    try:
        values = values.astype(np.float64)
    except (TypeError, ValueError):
        raise InputError(name, f"must be numbers, got dtype {values.dtype}") from None
    bad = np.isinf(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(name, f"must be finite (or NaN where missing), got "
                         f"{float(values[i])!r} in row {i}")
    return values


def check_range(values, name, ok, what):
    """Refuse the first value (NaN aside) that ``ok`` rejects: ``what``, naming the row."""
    bad = ~ok(values) & ~np.isnan(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(name, f"{what}, got {float(values[i])!r} in row {i}")


RANGES = {
    "pitch_speed": (lambda v: v > 0.0, "must be > 0 mph"),
    "vertical_approach_angle": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "horizontal_approach_angle": (lambda v: np.abs(v) < 90.0,
                                  "must lie within (-90, 90) deg"),
    "spin_rate": (lambda v: v >= 0.0, "must be >= 0 rpm"),
    "launch_speed": (lambda v: v > 0.0, "must be > 0 mph"),
    "launch_angle": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "spray_angle": (lambda v: np.abs(v) <= 180.0, "must lie within [-180, 180] deg"),
    "bat_speed": (lambda v: v > 0.0, "must be > 0 mph"),
    "attack_angle": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "attack_direction": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "spin_axis": (lambda v: np.abs(v) <= 360.0, "must lie within [-360, 360] deg"),
}
