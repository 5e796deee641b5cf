"""The units ``mcbat.stats.compare.comparison.compare`` knows, converts between, and suspects: a
measured column that states no unit is read in the simulated column's, and refused when
its values look like another unit of the same quantity."""

from __future__ import annotations

import math

import numpy as np

from mcbat.errors import InputError
from mcbat.study.units import UNITS

__all__ = ["PLAUSIBLE_MEDIANS", "PLAUSIBLE_ROWS", "UNIT_FACTORS", "UNIT_MATCH", "UNIT_SUSPICION",
           "column_values", "convert", "unit_contradiction", "unit_suspicion"]

_SPEED, _ANGLE, _SPIN, _LENGTH, _MASS = (UNITS[q] for q in ("speed", "angle", "spin", "length",
                                                            "mass"))
UNIT_FACTORS = {
    # unit: (quantity, factor to SI); the factors of mcbat.study.units where it has the unit
    "mph": ("speed", _SPEED["mph"]), "m/s": ("speed", 1.0), "km/h": ("speed", _SPEED["km/h"]),
    "ft/s": ("speed", _SPEED["ft/s"]),
    "deg": ("angle", _ANGLE["deg"]), "rad": ("angle", 1.0),
    "rpm": ("spin", _SPIN["rpm"]), "rad/s": ("spin", 1.0),
    "ft": ("length", _LENGTH["ft"]), "m": ("length", 1.0), "in": ("length", _LENGTH["in"]),
    "cm": ("length", _LENGTH["cm"]), "mm": ("length", _LENGTH["mm"]),
    "s": ("time", 1.0),
    "kg": ("mass", 1.0), "g": ("mass", _MASS["g"]), "oz": ("mass", _MASS["oz"]),
    "J": ("energy", 1.0), "kg m/s": ("momentum", 1.0), "kg m^2": ("inertia", 1.0),
    "1": ("ratio", 1.0),
}
"""The units ``mcbat.stats.compare.comparison.compare`` knows, and converts between within one
quantity. A column whose unit is not here (codes, identifiers) is not compared."""

UNIT_SUSPICION = 1.5
"""A column whose unit the measured table does not state is read in the simulated column's
unit; it is refused when the measured values' median magnitude differs from the simulated
one by more than this factor *and* lies within ``UNIT_MATCH`` of the factor between that
unit and another of its quantity (launch speeds in m/s: 0.447 of mph)."""
UNIT_MATCH = 1.3
"""See ``UNIT_SUSPICION``."""


PLAUSIBLE_MEDIANS = {
    # column: (unit, low, high): where the median of real measured values lies
    "launch_speed": ("mph", 50.0, 125.0),   # batted balls (bunts and dribblers included)
    "exit_speed": ("mph", 50.0, 125.0),
    "pitch_speed": ("mph", 45.0, 110.0),    # at the plate: eephus to the fastest fastball
    "bat_speed": ("mph", 40.0, 100.0),
    "spin_rate": ("rpm", 300.0, 6000.0),    # a batted ball's
    "pitch_spin_rate": ("rpm", 300.0, 4000.0),
    "backspin": ("rpm", -6000.0, 6000.0),
    "hit_distance": ("ft", 10.0, 500.0),
    "launch_angle": ("deg", -60.0, 80.0),
    "spray_angle": ("deg", -50.0, 50.0),
    "attack_angle": ("deg", -45.0, 60.0),
    "attack_direction": ("deg", -60.0, 60.0),
    "pitch_vertical_approach_angle": ("deg", -20.0, 5.0),
    "pitch_horizontal_approach_angle": ("deg", -15.0, 15.0),
}
"""Where the median of a column's real values lies, in its Statcast unit: a measured
column whose stated unit puts its median outside is refused
(``unit_contradiction``): launch speeds near 90 stated in m/s would be 200 mph, launch
speeds near 40 stated in mph slower than the batted balls of any table. The ranges are wide
(a table of one batter's or one pitch type's balls lies inside); they catch a unit off by
the factor between two units of the quantity, not every mistake."""
PLAUSIBLE_ROWS = 10
"""The fewest values whose median ``unit_contradiction`` judges."""


def unit_contradiction(column, measured, unit):
    """An ``mcbat.errors.InputError`` about ``column`` when the median of
    ``measured`` (finite values, stated to be in ``unit``) lies outside where the column's
    real values lie (``PLAUSIBLE_MEDIANS``), else None. The message names the column,
    the unit, the median and, when one puts it in range, the unit the values look like."""
    if column not in PLAUSIBLE_MEDIANS or unit not in UNIT_FACTORS:
        return None
    expected, low, high = PLAUSIBLE_MEDIANS[column]
    kind = UNIT_FACTORS[expected][0]
    values = np.asarray(measured, dtype=float)
    values = values[np.isfinite(values)]
    if UNIT_FACTORS[unit][0] != kind or values.size < PLAUSIBLE_ROWS:
        return None
    median = float(np.median(values))
    as_expected = median * UNIT_FACTORS[unit][1] / UNIT_FACTORS[expected][1]
    if low <= as_expected <= high:
        return None
    fits = [other for other, (other_kind, factor) in UNIT_FACTORS.items()
            if other_kind == kind and other != unit
            and low <= median * factor / UNIT_FACTORS[expected][1] <= high]
    centre = math.sqrt(abs(low * high)) if low > 0 else 0.5 * (low + high)
    fits.sort(key=lambda other: abs(median * UNIT_FACTORS[other][1]
                                    / UNIT_FACTORS[expected][1] - centre))
    hint = f"; the values look like {fits[0]}: state that unit ({{units}})" if fits else ""
    return InputError(
        column, f"stated in {unit}, but the values' median {median:.4g} {unit}"
        f"{'' if unit == expected else f' ({as_expected:.4g} {expected})'} lies outside "
        f"{low:g}..{high:g} {expected}, where the "
        f"median of real {column} lies: the stated unit contradicts the values{hint}",
        mentions={"units": {column: fits[0]}} if fits else None)


def convert(values, unit, to):
    """``values`` in ``unit`` expressed in ``to`` (both in ``UNIT_FACTORS``, of one
    quantity)."""
    if unit == to:
        return np.asarray(values, dtype=float)
    (kind, factor), (kind_to, factor_to) = UNIT_FACTORS[unit], UNIT_FACTORS[to]
    if kind != kind_to:
        raise InputError(None, f"cannot convert {unit} ({kind}) to {to} ({kind_to})")
    return np.asarray(values, dtype=float) * (factor / factor_to)


def unit_suspicion(column, simulated, measured, unit):
    """An ``mcbat.errors.InputError`` about ``column`` when ``measured`` (whose table
    states no unit, read in ``unit``) looks like another unit of the same quantity, else
    None (``UNIT_SUSPICION``). The ``units`` it advises is a mention (data), so a
    command line can spell it as its flag."""
    kind = UNIT_FACTORS[unit][0]
    if kind in ("ratio",):
        return None
    typical_sim = float(np.median(np.abs(simulated)))
    typical_meas = float(np.median(np.abs(measured)))
    if typical_sim <= 0 or typical_meas <= 0:
        return None
    ratio = typical_meas / typical_sim
    if abs(math.log(ratio)) <= math.log(UNIT_SUSPICION):
        return None
    for other, (other_kind, factor) in UNIT_FACTORS.items():
        if other_kind != kind or other == unit:
            continue
        expected = UNIT_FACTORS[unit][1] / factor  # a value in `other` read as `unit`
        if abs(math.log(ratio / expected)) < math.log(UNIT_MATCH):
            return InputError(
                column, f"the measured values' median magnitude ({typical_meas:.4g}) is "
                f"{ratio:.3g} times the simulated one ({typical_sim:.4g} {unit}), close "
                f"to the {expected:.3g} of a value in {other}: wrong unit? The table "
                f"states no unit for {column}, so it is read in {unit}; state its unit to "
                f"compare it converted ({{units}}), or state it as {unit} to compare the "
                f"values as they are", mentions={"units": {column: other}})
    return None


def column_values(name, sim_series, meas_series, sim_unit, meas_unit):
    """Both sides' finite values in the unit of comparison (the measured table's stated
    unit, else the simulated one), the unit, the unit converted from, and the counts of
    dropped rows."""
    sim = sim_series.to_numpy(dtype=float)
    meas = meas_series.to_numpy(dtype=float)
    sim_ok, meas_ok = np.isfinite(sim), np.isfinite(meas)
    unit = meas_unit or sim_unit
    sim_values = convert(sim[sim_ok], sim_unit, unit)
    return sim_values, meas[meas_ok], unit, (None if unit == sim_unit else sim_unit), \
        int((~sim_ok).sum()), int((~meas_ok).sum())
