"""Units accepted in study files, and their conversion to SI.

Every numeric input of a study has a *quantity* (length, speed, ...). Its values may be
written in any unit of that quantity (``unit = "cm"``); without a unit they are SI. The
factors are the exact definitions of ``mcbat.core.units`` (the international inch, foot
and mile per hour, ``1 km/h = 1/3.6 m/s``, ``1 rpm = 2 pi / 60 rad/s`` with the double
nearest pi), and the
conversion is exact: the value as written (its shortest decimal form) times the factor,
in rational arithmetic, rounded once to the nearest double. So ``15 cm`` is exactly
``0.15`` and ``1.5 in`` exactly ``0.0381``.

===============  =========  ==========================================
quantity         SI unit    accepted units
===============  =========  ==========================================
length           m          m, cm, mm, in, ft
speed            m/s        m/s, km/h, mph, ft/s
spin             rad/s      rad/s, rpm, rps
angle            rad        rad, deg
mass             kg         kg, g, oz, lb
inertia          kg m^2     kg m^2 (also written kg*m^2), g cm^2
temperature      K          K, degC, degF (affine: ``degF`` is ``(F - 32) 5/9 + 273.15`` K)
pressure         Pa         Pa, hPa, kPa, inHg, mmHg (``1 inHg = 3386.389 Pa``,
                            ``1 mmHg = 133.322387415 Pa``)
dimensionless    1          1
===============  =========  ==========================================

Temperatures convert with their offsets (``to_si``); ``factor`` gives the scale of a
temperature *difference* (a width), ``5/9`` for ``degF``.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from mcbat.core.units import (
    EXACT,
    KG_PER_LB,
    KG_PER_OZ,
    M_PER_FT,
    M_PER_IN,
    M_S_PER_MPH,
    PA_PER_INHG,
    PA_PER_MMHG,
    RAD_PER_DEG,
    RAD_S_PER_RPM,
)
from mcbat.errors import InputError

__all__ = ["ANGLE", "DIMENSIONLESS", "INERTIA", "LENGTH", "MASS", "PRESSURE", "SI_UNITS",
           "SPEED", "SPIN", "TEMPERATURE", "UNITS", "_EXACT", "factor", "format_value",
           "to_si"]

LENGTH = "length"
SPEED = "speed"
SPIN = "spin"
ANGLE = "angle"
MASS = "mass"
INERTIA = "inertia"
TEMPERATURE = "temperature"
PRESSURE = "pressure"
DIMENSIONLESS = "dimensionless"

#: Conversion factor to SI of every accepted unit, by quantity.
UNITS: dict[str, dict[str, float]] = {
    LENGTH: {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": M_PER_IN, "ft": M_PER_FT},
    SPEED: {"m/s": 1.0, "km/h": 1.0 / 3.6, "mph": M_S_PER_MPH, "ft/s": M_PER_FT},
    SPIN: {"rad/s": 1.0, "rpm": RAD_S_PER_RPM, "rps": 2.0 * math.pi},
    ANGLE: {"rad": 1.0, "deg": RAD_PER_DEG},
    MASS: {"kg": 1.0, "g": 0.001, "oz": KG_PER_OZ, "lb": KG_PER_LB},
    INERTIA: {"kg m^2": 1.0, "kg*m^2": 1.0, "g cm^2": 1e-7},
    TEMPERATURE: {"K": 1.0, "degC": 1.0, "degF": 5.0 / 9.0},
    PRESSURE: {"Pa": 1.0, "hPa": 100.0, "kPa": 1000.0, "inHg": PA_PER_INHG,
               "mmHg": PA_PER_MMHG},
    DIMENSIONLESS: {"1": 1.0},
}

_PI = Fraction(math.pi)
# The exact factors behind UNITS.
_EXACT: dict[str, dict[str, Fraction]] = {
    LENGTH: {"m": Fraction(1), "cm": Fraction("0.01"), "mm": Fraction("0.001"),
             "in": EXACT["m_per_in"], "ft": EXACT["m_per_ft"]},
    SPEED: {"m/s": Fraction(1), "km/h": Fraction(10, 36), "mph": EXACT["m_s_per_mph"],
            "ft/s": EXACT["m_per_ft"]},
    SPIN: {"rad/s": Fraction(1), "rpm": 2 * _PI / 60, "rps": 2 * _PI},
    ANGLE: {"rad": Fraction(1), "deg": _PI / 180},
    MASS: {"kg": Fraction(1), "g": Fraction("0.001"), "oz": EXACT["kg_per_oz"],
           "lb": EXACT["kg_per_lb"]},
    INERTIA: {"kg m^2": Fraction(1), "kg*m^2": Fraction(1), "g cm^2": Fraction("1e-7")},
    TEMPERATURE: {"K": Fraction(1), "degC": Fraction(1), "degF": Fraction(5, 9)},
    PRESSURE: {"Pa": Fraction(1), "hPa": Fraction(100), "kPa": Fraction(1000),
               "inHg": EXACT["pa_per_inhg"], "mmHg": EXACT["pa_per_mmhg"]},
    DIMENSIONLESS: {"1": Fraction(1)},
}
# Temperatures: K = (value - _ZERO[unit]) * factor + 273.15 for degC/degF.
_ZERO = {"degC": Fraction(0), "degF": Fraction(32)}
_KELVIN_AT_ZERO_C = Fraction("273.15")

#: The SI unit of each quantity (what values without a ``unit`` are taken to be).
SI_UNITS: dict[str, str] = {
    LENGTH: "m", SPEED: "m/s", SPIN: "rad/s", ANGLE: "rad", MASS: "kg",
    INERTIA: "kg m^2", TEMPERATURE: "K", PRESSURE: "Pa", DIMENSIONLESS: "1",
}

_QUANTITY_OF = {unit: quantity for quantity, table in UNITS.items() for unit in table}


def _article(word):
    """``"an angle"``, ``"a length"``."""
    return f"{'an' if word[0] in 'aeiou' else 'a'} {word}"


def factor(unit, quantity, field=None):
    """SI factor of ``unit`` (``None``: the SI unit, factor 1) for a ``quantity``.

    Raises
    ------
    InputError
        On ``field``: an unknown unit, a unit of another quantity, or a non-string unit.
    """
    if quantity not in UNITS:
        raise ValueError(f"unknown quantity {quantity!r} (expected one of: {', '.join(UNITS)})")
    if unit is None:
        return 1.0
    accepted = ", ".join(UNITS[quantity])
    if not isinstance(unit, str):
        raise InputError(field, f"unit must be a string, got {unit!r} "
                                f"({quantity} units: {accepted})")
    table = UNITS[quantity]
    if unit in table:
        return table[unit]
    other = _QUANTITY_OF.get(unit)
    if other is not None:
        kind = "dimensionless" if quantity == DIMENSIONLESS else _article(quantity)
        raise InputError(field, f"unit {unit!r} is {_article(other)} unit, but this input is "
                                f"{kind} (use one of: {accepted})")
    raise InputError(field, f"unknown unit {unit!r} ({quantity} units: {accepted})")


def to_si(value_or_array, unit, quantity, field=None):
    """Convert a value (or array of values) written in ``unit`` to SI.

    Parameters
    ----------
    value_or_array : float or array_like
        The value(s) as written.
    unit : str or None
        One of ``UNITS`` ``[quantity]``; ``None`` means the values are already SI.
    quantity : str
        ``"length"``, ``"speed"``, ``"spin"``, ``"angle"``, ``"mass"``, ``"inertia"`` or
        ``"dimensionless"``.
    field : str, optional
        Dotted name of the input, for the error message.

    Returns
    -------
    float or ndarray
        A float for a scalar input, else a float64 array.

    Raises
    ------
    InputError
        For an unknown unit or a unit of another quantity (naming ``field``).

    Examples
    --------
    >>> to_si(90.0, "mph", "speed")
    40.2336
    >>> to_si(15, "cm", "length")
    0.15
    """
    factor(unit, quantity, field)  # validates the unit
    try:
        return _to_si(value_or_array, unit, quantity)
    except OverflowError:
        raise InputError(field, f"too large: {value_or_array!r} {unit} is beyond the largest "
                         "floating-point number once converted to SI") from None


def _to_si(value_or_array, unit, quantity):
    if quantity == TEMPERATURE and unit in _ZERO:
        values = np.asarray(value_or_array, dtype=np.float64)
        out = np.array([_temperature(float(v), unit) for v in values.ravel()],
                       dtype=np.float64).reshape(values.shape)
        return float(out) if np.ndim(value_or_array) == 0 else out
    if unit is None or _EXACT[quantity][unit] == 1:
        if np.ndim(value_or_array) == 0:
            return float(value_or_array)
        return np.array(value_or_array, dtype=np.float64)
    exact = _EXACT[quantity][unit]
    if np.ndim(value_or_array) == 0:
        return _convert(float(value_or_array), exact)
    values = np.asarray(value_or_array, dtype=np.float64)
    return np.array([_convert(float(v), exact) for v in values.ravel()],
                    dtype=np.float64).reshape(values.shape)


def _temperature(value, unit):
    """A temperature in ``unit`` (degC or degF) in K, exact then rounded once."""
    if not math.isfinite(value):
        return value
    return float((Fraction(repr(value)) - _ZERO[unit]) * _EXACT[TEMPERATURE][unit]
                 + _KELVIN_AT_ZERO_C)


def _convert(value, exact):
    """``value * exact``, the value read as its shortest decimal, rounded once (an
    OverflowError when the product exceeds the largest float)."""
    if not math.isfinite(value):
        return value * float(exact)
    return float(Fraction(repr(value)) * exact)


def format_value(si_value, raw_value, unit, quantity):
    """``"2.5 in (= 0.0635 m)"`` or ``"0.0635 m"``: a value as written and in SI."""
    si_unit = SI_UNITS[quantity]
    si_text = f"{si_value:.6g}" if quantity == DIMENSIONLESS else f"{si_value:.6g} {si_unit}"
    if unit is None or unit == si_unit:
        return f"{raw_value!r}" if quantity == DIMENSIONLESS else f"{raw_value!r} {si_unit}"
    return f"{raw_value!r} {unit} (= {si_text})"
