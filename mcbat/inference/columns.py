"""The measured table an inference reads: its columns, their units and ranges, each
column read and checked (naming the column and the row); the result's columns."""

from __future__ import annotations

import numpy as np

from mcbat.errors import InputError
from mcbat.solving.inference import INFERENCE_STATUS_NAMES

__all__ = ["INPUT_COLUMNS", "OPTIONAL_COLUMNS", "OUTPUT_UNITS", "RANGES", "SPRAY_BEHIND",
           "STATUS_NAMES",
           "SWING_COLUMNS", "SWING_RANGES", "TEXT_COLUMNS", "bunt_rows", "check_range",
           "numeric_column", "read_column", "unusable_swing_rows"]

INPUT_COLUMNS = {
    "pitch_speed": "mph", "vertical_approach_angle": "deg",
    "horizontal_approach_angle": "deg", "spin_rate": "rpm", "handedness": "R/L",
    "launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
}
"""Required columns (Statcast's tidy names, ``mcbat.statcast.read``) and their units: the
pitch at the plate (speed, approach angles: vertical < 0 descending, horizontal > 0
moving towards first base; spin rate), the batter's side, and the batted ball."""

OPTIONAL_COLUMNS = {"spin_axis": "deg", "bat_speed": "mph", "attack_angle": "deg",
                    "attack_direction": "deg", "swing_path_tilt": "deg"}
"""Optional columns. ``spin_axis`` (Statcast's clock-face convention, 180 = pure
backspin; NaN or absent: ``SpinAssumptions.spin_axis``); ``bat_speed`` (where
finite, used, and the contact position inferred instead); ``attack_angle`` (where
finite, used instead of ``SpinAssumptions.attack_angle``); ``swing_path_tilt`` (where
finite and below 90 deg, the vertical bat angle follows from it and the attack angle,
``mcbat.study.swing_plane``, instead of ``SpinAssumptions.vertical_bat_angle``);
``attack_direction`` is
not an input: it is one of the unknowns that reproduce the spray angle
(``docs/spin_inference.md``), but a swing aimed 90 deg or more off the pitch's line (a
bunt) makes the row's swing unusable."""

SWING_COLUMNS = ("bat_speed", "attack_angle", "attack_direction")
"""The optional columns of the measured swing (bat tracking). A value out of range
never refuses the table: the row's swing is unusable (``unusable_swing``)."""

TEXT_COLUMNS = ("description", "events", "des")
"""Optional text columns (Savant's) read to tell a bunt: ``description`` (``foul_bunt``,
``missed_bunt``, ``bunt_foul_tip``), ``events`` (``sac_bunt``,
``sac_bunt_double_play``), ``des`` ("... bunt grounds out ...", "... on a bunt ground
ball ...")."""

STATUS_NAMES = (*INFERENCE_STATUS_NAMES.values(), "missing_input", "unusable_swing",
                "bat_speed_inconsistent")
"""Values of the ``inference_status`` column: ``missing_input`` for a row with a NaN in
a required column (with ``missing="flag"``); ``unusable_swing`` for a row whose measured
swing the model cannot use (a bunt, a bat speed below
``InferenceOptions.bat_speed_floor``, a swing value out of range or partly missing);
``bat_speed_inconsistent`` where no bat speed within
``InferenceOptions.bat_speed_error`` of the measured one gives the ball."""

SPRAY_BEHIND = 90.0
"""deg: a ``spray_angle`` beyond it (the ball fielded behind the line through home plate
square to centre field: a pop-up the catcher caught, a dribbler bouncing back) gives no
launch direction (the direction from home to where a ball was fielded is its launch's only
for a ball that travelled out). Such a ball is solved with a straightaway launch (spray 0)
and ``spray_observed`` False: its backspin follows from the launch speed and angle, its
sidespin and attack direction are those of the straightaway launch, not measured."""

OUTPUT_UNITS = {
    "inference_status": "", "inferred": "", "backspin": "rpm", "sidespin": "rpm",
    "gyrospin": "rpm", "spin_rate": "rpm", "undercut": "m", "bat_speed": "mph",
    "from_barrel_end": "m", "attack_direction": "deg", "attack_angle": "deg",
    "collision_efficiency": "1", "bat_speed_adjustment": "mph", "inference_iterations": "",
    "kernel_evaluations": "", "spray_observed": "",
}
"""Columns of ``infer_spin``'s result and their units."""


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
    "spin_axis": (lambda v: np.abs(v) <= 360.0, "must lie within [-360, 360] deg"),
}
"""Ranges of the required columns and of ``spin_axis``: a value outside refuses the table
(``mcbat.errors.InputError`` naming the column and the row)."""

SWING_RANGES = {
    "bat_speed": lambda v: v > 0.0,
    "attack_angle": lambda v: np.abs(v) < 90.0,
    "attack_direction": lambda v: np.abs(v) < 90.0,
}
"""Ranges of ``SWING_COLUMNS``: a value outside makes the row's swing unusable."""


def swing_column(table, name, n):
    """An optional swing column as float64, NaN where absent or missing; infinite or
    non-numeric cells become NaN and are returned as a mask of bad cells."""
    values = read_column(table, name, n, required=False)
    if values is None:
        return np.full(n, np.nan), np.zeros(n, dtype=bool)
    import pandas as pd

    numbers = np.array(pd.to_numeric(pd.Series(values), errors="coerce")
                       .to_numpy(dtype=float, na_value=np.nan))
    given = ~pd.isna(pd.Series(values)).to_numpy()
    bad = (given & np.isnan(numbers)) | np.isinf(numbers)
    numbers[bad] = np.nan
    return numbers, bad


def bunt_rows(table, n):
    """Rows Savant marks as bunts (``mcbat.statcast.is_bunt`` on the
    ``TEXT_COLUMNS`` present): boolean array."""
    from mcbat.statcast.collision import is_bunt

    text = {name: read_column(table, name, n, required=False) for name in TEXT_COLUMNS}
    if all(v is None for v in text.values()):
        return np.zeros(n, dtype=bool)
    return is_bunt(**text)


def unusable_swing_rows(swing, bad, bunts, floor):
    """Why each row's measured swing cannot be used, as a dict of boolean arrays:
    ``bunt`` (Savant's text, or ``|attack_direction| >= 90`` deg), ``below_floor``
    (``bat_speed`` below ``floor`` mph, or not > 0), ``out_of_range`` (an attack angle
    beyond +-90 deg, a cell that is not a finite number), ``partly_missing`` (a bat
    speed without the attack angle where the table measures attack angles)."""
    speed = swing["bat_speed"]
    tracked = np.isfinite(speed)
    direction = swing["attack_direction"]
    reasons = {
        "bunt": bunts | (np.isfinite(direction) & ~SWING_RANGES["attack_direction"](direction)),
        "below_floor": tracked & ~(speed >= floor),
        "out_of_range": np.zeros(speed.shape, dtype=bool),
        "partly_missing": np.zeros(speed.shape, dtype=bool),
    }
    angle = swing["attack_angle"]
    reasons["out_of_range"] |= np.isfinite(angle) & ~SWING_RANGES["attack_angle"](angle)
    for mask in bad.values():
        reasons["out_of_range"] |= mask
    if np.isfinite(angle).any():
        reasons["partly_missing"] = tracked & np.isnan(angle)
    return reasons
