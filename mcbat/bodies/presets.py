"""Ball and bat presets of study files (``preset = "..."``), and the bodies they describe.

Balls
    ``"baseball"``: 0.145 kg, radius 0.036 m, ``I = 0.4 m R^2`` (the paper's Sec. V;
    ``docs/physics.md``).
    ``"regulation"``: a regulation baseball as Nathan's trajectory calculator takes it:
    5.125 oz (0.14529 kg) and a circumference of 9.125 in (radius 0.036888 m), the middle
    of the rules' 5-5.25 oz and 9-9.25 in (Official Baseball Rules 3.01); ``I = 0.4 m R^2``.
    The default ball of game cases and flights; the paper's reproduction keeps
    ``"baseball"``.
Bats
    ``"cross_nathan_2006"``: the Sec. V bat of ``docs/physics.md`` (Cross & Nathan's experiment):
    0.989 kg, ``I_t = 0.046``, ``I_3 = 4.39e-4`` kg m^2, length 0.84 m, CM 0.265 m from the
    barrel end, and a cylinder of radius 0.03335 m at the contact (wherever it is).

    ``"r161"``: the Louisville Slugger R161 wood profile (``mcbat.bodies.tables.r161_profile``,
    uniform density 649 kg/m^3): tapered, so the radius and slope at the contact come from
    the profile, and so do the mass properties.
"""

from __future__ import annotations

import math

from mcbat.bodies.ball import Ball
from mcbat.bodies.bat import Bat
from mcbat.bodies.tables import r161_profile

__all__ = ["BALL_PRESETS", "DEFAULT_BALL", "BAT_PRESETS", "ball_preset", "bat_preset"]

#: Ball presets.
BALL_PRESETS = {
    "baseball": Ball(mass=0.145, radius=0.036, inertia_factor=0.4, preset="baseball"),
    "regulation": Ball(mass=5.125 * 0.028349523125, radius=9.125 * 0.0254 / (2.0 * math.pi),
                       inertia_factor=0.4, preset="regulation"),
}
#: The ball of game cases and flights when none is given.
DEFAULT_BALL = "regulation"


def _cross_nathan_2006():
    return Bat(mass=0.989, transverse_inertia=0.046, axial_inertia=4.39e-4,
                   radius=0.03335, length=0.84, cm_from_barrel_end=0.265,
                   preset="cross_nathan_2006")


def _r161():
    return Bat.from_profile(r161_profile(), preset="r161")


_BAT_FACTORIES = {"cross_nathan_2006": _cross_nathan_2006, "r161": _r161}

#: Names of the bat presets.
BAT_PRESETS = tuple(_BAT_FACTORIES)


def ball_preset(name) -> Ball:
    """The ball preset ``name`` (KeyError if unknown)."""
    return BALL_PRESETS[name]


def bat_preset(name) -> Bat:
    """A new ``mcbat.bodies.bat.Bat`` for the bat preset ``name`` (KeyError if unknown)."""
    return _BAT_FACTORIES[name]()
