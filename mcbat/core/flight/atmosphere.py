"""Air density from the weather, as in Nathan's trajectory calculator (``README.md``)."""

import math

from mcbat.core.jit import njit

__all__ = ["MMHG_PER_PA", "air_density", "saturation_vapour_pressure"]

#: mmHg per pascal.
MMHG_PER_PA = 760.0 / 101325.0
#: Fall of the pressure with elevation in the calculator's formula (1/m).
_BETA = 1.217e-4


@njit
def saturation_vapour_pressure(temperature):
    """Saturation vapour pressure (mmHg) at ``temperature`` (degC), the calculator's fit."""
    t = temperature
    return 4.5841 * math.exp((18.687 - t / 234.5) * t / (257.14 + t))


@njit
def air_density(temperature, pressure, relative_humidity, elevation):
    """Density of moist air (kg/m^3).

    Parameters
    ----------
    temperature : float
        degC.
    pressure : float
        Barometric pressure corrected to sea level, as weather reports give it (Pa).
    relative_humidity : float
        Percent (0-100).
    elevation : float
        m above sea level.
    """
    p_mmhg = pressure * MMHG_PER_PA
    vapour = 0.3783 * relative_humidity * saturation_vapour_pressure(temperature) / 100.0
    return (1.2929 * (273.0 / (temperature + 273.0))
            * (p_mmhg * math.exp(-_BETA * elevation) - vapour) / 760.0)
