"""The unit conversions of the whole package, in one place at the bottom of it.

Each name says its direction: ``M_PER_FT`` is metres per foot, so ``feet * M_PER_FT`` is
metres and ``metres / M_PER_FT`` feet. The factors are the exact definitions (the
international foot, inch, mile per hour, ounce and pound; the inch of mercury of
Nathan's calculator) or, for angles and spins, the double nearest the exact value.
``EXACT`` holds the defined factors as fractions, for conversions that must round once.
"""

import math
from fractions import Fraction
from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = ["DEG_PER_RAD", "EXACT", "FT_S_PER_MPH", "KG_PER_LB", "KG_PER_OZ", "M_PER_FT",
           "M_PER_IN", "M_S_PER_MPH", "PA_PER_INHG", "PA_PER_MMHG", "RAD_PER_DEG",
           "RAD_S_PER_RPM", "RPM_PER_RAD_S", "celsius_from_fahrenheit",
           "kelvin_from_fahrenheit"]

#: Exact definitions (fractions).
EXACT = {"m_per_ft": Fraction("0.3048"), "m_per_in": Fraction("0.0254"),
         "m_s_per_mph": Fraction("0.44704"), "kg_per_oz": Fraction("0.028349523125"),
         "kg_per_lb": Fraction("0.45359237"), "pa_per_inhg": Fraction("3386.389"),
         "pa_per_mmhg": Fraction("133.322387415")}

#: Metres per foot.
M_PER_FT = float(EXACT["m_per_ft"])
#: Metres per inch.
M_PER_IN = float(EXACT["m_per_in"])
#: Metres per second per mile per hour.
M_S_PER_MPH = float(EXACT["m_s_per_mph"])
#: Feet per second per mile per hour (5280 / 3600).
FT_S_PER_MPH = 5280.0 / 3600.0
#: Kilograms per ounce (avoirdupois).
KG_PER_OZ = float(EXACT["kg_per_oz"])
#: Kilograms per pound.
KG_PER_LB = float(EXACT["kg_per_lb"])
#: Pascals per inch of mercury (Nathan's calculator's).
PA_PER_INHG = float(EXACT["pa_per_inhg"])
#: Pascals per millimetre of mercury.
PA_PER_MMHG = float(EXACT["pa_per_mmhg"])
#: Radians per degree.
RAD_PER_DEG = math.pi / 180.0
#: Degrees per radian.
DEG_PER_RAD = 180.0 / math.pi
#: Radians per second per revolution per minute.
RAD_S_PER_RPM = 2.0 * math.pi / 60.0
#: Revolutions per minute per radian per second.
RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


#: A temperature: a float or an array of them (each conversion gives what it takes).
_Temperature = TypeVar("_Temperature", float, NDArray[np.float64])


def celsius_from_fahrenheit(temperature: _Temperature) -> _Temperature:
    """DegC from degF (scalars or arrays)."""
    return (temperature - 32.0) * 5.0 / 9.0


def kelvin_from_fahrenheit(temperature: _Temperature) -> _Temperature:
    """K from degF (scalars or arrays)."""
    return celsius_from_fahrenheit(temperature) + 273.15
