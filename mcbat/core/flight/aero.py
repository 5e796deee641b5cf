"""Drag and lift coefficients of a spinning baseball, by model (``README.md``).

Models (integer codes, so jitted code can branch on them):

``NATHAN`` (0)
    Nathan's calculator: ``C_D = 0.3008 + 0.0292 (spin / 1000 rpm) D``,
    ``C_L = 1.120 S / (0.583 + 2.333 S)``, ``S = R |omega| D / |v|``.
``SAWICKI2003`` (1)
    Sawicki, Hubbard & Stronge (2003)'s lift, ``C_L = 1.5 S`` for ``S < 0.1`` and
    ``0.09 + 0.6 S`` above, with the calculator's drag (their drag-crisis profile is not
    in the project's sources, so it is not reproduced).
``CONSTANT`` (2)
    Given ``C_D`` and ``C_L``.

``D`` is the spin decay factor (1 without decay). ``drag_scale`` multiplies the spin-free
drag ``C_D0`` (0.3008) and ``lift_scale`` the lift of ``NATHAN`` and ``SAWICKI2003``: a
calibration of the model to measured distances (``docs/flight.md``); 1 and 1 are the
published models, bit for bit.
"""

from collections import namedtuple

from mcbat.core.jit import njit
from mcbat.core.units import RPM_PER_RAD_S

__all__ = ["CONSTANT", "MODELS", "NATHAN", "SAWICKI2003", "Aero", "coefficients"]

NATHAN = 0
SAWICKI2003 = 1
CONSTANT = 2
#: Model name -> code.
MODELS = {"nathan": NATHAN, "sawicki2003": SAWICKI2003, "constant": CONSTANT}


Aero = namedtuple("Aero", ("model", "drag", "lift", "drag_scale", "lift_scale"))
"""The model's code, ``C_D``, ``C_L`` (used by ``CONSTANT`` only), and the scales of the
spin-free drag ``C_D0`` and of the lift (not used by ``CONSTANT``)."""


@njit(inline="always")
def coefficients(aero, radius, spin, speed, decay):
    """``(C_D, C_L)`` for spin ``spin`` (rad/s, before decay), air speed ``speed`` (m/s),
    decay factor ``decay`` and ball radius ``radius`` (m)."""
    if aero.model == CONSTANT:
        return aero.drag, aero.lift
    drag = 0.3008 * aero.drag_scale + 0.0292 * (spin * RPM_PER_RAD_S / 1000.0) * decay
    s = radius * spin * decay / speed if speed > 0.0 else 0.0
    if aero.model == NATHAN:
        return drag, aero.lift_scale * (1.120 * s / (0.583 + 2.333 * s))
    return drag, aero.lift_scale * (1.5 * s if s < 0.1 else 0.09 + 0.6 * s)
