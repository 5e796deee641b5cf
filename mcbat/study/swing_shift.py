"""What if every swing were another: ``[pitches.swing_shift]``.

With ``[pitches] swing = true`` a study meets each real pitch with the swing Statcast
measured for it. ``[pitches.swing_shift]`` adds a fixed amount to every drawn swing's
``bat_speed``, ``attack_angle`` or ``attack_direction`` (after the true value is drawn
given the measured one, ``[pitches.swing_error]``), so that a study answers "the same
pitches, each swing 2 mph faster" or "3 degrees more uppercut" through the collision
model; every other setting, the contact included, stays the study's. With
``swing_plane = true`` the bat's vertical angle follows the shifted attack angle in the
measured plane. The shifted values are held inside the study's ranges as the true values
are (``mcbat.study.swing_errors.clip_true``).
"""

from __future__ import annotations

import math
from types import MappingProxyType

import numpy as np

from mcbat.errors import InputError
from mcbat.study.distributions import parse
from mcbat.study.swing_errors import clip_true, swing_table

__all__ = ["SHIFTED", "apply_swing_shift", "parse_swing_shift"]

SHIFTED = ("bat_speed", "attack_angle", "attack_direction")
"""The swing keys a shift may move."""


def parse_swing_shift(table, swing, quantities) -> MappingProxyType:
    """``[pitches]``'s ``[pitches.swing_shift]`` -> study key (``"swing.bat_speed"``) ->
    the amount added (SI: m/s or rad). ``quantities``: each key's physical quantity."""
    shifts = swing_table(table, "swing_shift", swing, SHIFTED,
                         "it moves the measured swings drawn from the rows")
    out = {}
    for key, spec in shifts.items():
        name = f"pitches.swing_shift.{key}"
        dist = parse(spec, name, quantities[key])
        if dist.family != "fixed" or not math.isfinite(dist.value):
            raise InputError(name, f"must be a fixed value (the amount added to every "
                             f"swing, e.g. {{ value = 2, unit = \"mph\" }}), got {spec!r}")
        out[f"swing.{key}"] = float(dist.value)
    return MappingProxyType(out)


def apply_swing_shift(cols, shift, targets, vertical_support=None) -> None:
    """Add each shift to its column of ``cols`` (``targets``: study key -> column name),
    in place, holding the values inside the study's ranges."""
    for key, amount in shift.items():
        column = cols[targets[key]]
        np.copyto(column, clip_true(key, column + amount, vertical_support))
