"""The paper's Sec. V configuration (Cross & Nathan's drop test): the one source of its
numbers in the package.

``docs/physics.md`` (Sec. V): ball 0.145 kg, R = 0.036 m, I = 0.4 m R^2; bat 0.989 kg,
barrel radius 0.03335 m, I_t = 0.046, I_3 = 4.39e-4 kg m^2, CM 0.265 m from the barrel end
(the bodies are the presets ``baseball`` and ``cross_nathan_2006``); contact plane
a = 0.115 m from the CM (15 cm from the barrel end); mu = 0.5; the ball falls along -x at
4 m/s with spin w0 about the bat axis, w0 in {+79, 0, -72} rad/s; the bat is at rest. The
numbers the paper prints are in ``data/paper_sec5_numbers.json``
(``printed_numbers``).
"""

from __future__ import annotations

import json
import math
from importlib import resources

from mcbat.api import Contact, ImpactCase
from mcbat.bodies import ball_preset, bat_preset

__all__ = ["AXIAL", "BALL", "BAT", "CM_FROM_BARREL_END", "CROSS_NATHAN_E_X", "LOSS_FRACTION",
           "MU", "REACH", "SPEED", "SPINS", "TARGET_SPEED", "THETA_NEAR_ZERO", "case",
           "case_at_impact_parameter", "e_star_paper", "printed_numbers"]


def printed_numbers() -> dict:
    """The numbers the paper prints in Sec. V, with provenance (the bundled
    ``data/paper_sec5_numbers.json``)."""
    return json.loads(resources.files("mcbat.data").joinpath("paper_sec5_numbers.json")
                      .read_text(encoding="utf-8"))


_PRINTED = printed_numbers()["values"]
BALL = ball_preset("baseball")
BAT = bat_preset("cross_nathan_2006")
CM_FROM_BARREL_END = BAT.cm_from_barrel_end  # m
AXIAL = 0.115  # m, contact plane 15 cm from the barrel end
MU = 0.5
SPEED = 4.0  # m/s, falling along -x
SPINS = (79.0, 0.0, -72.0)  # rad/s about the bat axis
THETA_NEAR_ZERO = math.pi / 400  # the paper's "nearly vanishing impact parameter"
LOSS_FRACTION = _PRINTED["loss_fraction_e2"]  # the paper's calibrated e^2, 0.6183822
CROSS_NATHAN_E_X = 0.16  # Cross & Nathan's tangential restitution fit (docs/physics.md)
TARGET_SPEED = _PRINTED["exit_speed"]  # m/s, 1.44629 at theta = pi/400, w0 = 0
REACH = BALL.radius + BAT.radius  # m, largest impact parameter that still hits


def e_star_paper() -> float:
    """The paper's calibration as an energetic coefficient, ``e* = sqrt(1 - e^2)``."""
    return math.sqrt(1.0 - LOSS_FRACTION)


def case(theta: float = THETA_NEAR_ZERO, w0: float = 0.0, *, mu: float = MU,
         e: float | None = None, axial: float = AXIAL, speed: float = SPEED,
         e_x: float = 0.0) -> ImpactCase:
    """The Sec. V impact at contact angle ``theta`` (rad) with incoming spin ``w0`` (rad/s).

    ``e`` is the energetic coefficient e* (default: the paper's calibration); ``e_x`` the
    tangential restitution (default 0: the paper's rigid model).
    """
    return ImpactCase(ball=BALL, bat=BAT, contact=Contact(axial=axial, angle=theta),
                      ball_velocity=(-speed, 0.0, 0.0), ball_spin=(0.0, 0.0, w0),
                      mu=mu, e=e_star_paper() if e is None else e, e_x=e_x)


def case_at_impact_parameter(b: float, w0: float = 0.0, **kwargs) -> ImpactCase:
    """The Sec. V impact for a ball line offset ``b`` (m) from the bat axis:
    ``b = (R + r_b) sin(theta)`` (docs/physics.md; the paper's ``cos`` is a misprint)."""
    return case(math.asin(b / REACH), w0, **kwargs)
