"""The numeric inputs of a bat-frame study: ``[contact]``, the four vector sections
(``[ball_velocity]``, ``[ball_spin]``, ``[bat_velocity]``, ``[bat_spin]``), ``[friction]``,
``[restitution]`` and the measurement noise of ``[noise]``; the solver column each input is
drawn into, and the columns of the inputs a study leaves out. The file format is described
in ``docs/study-format.md``.
"""

from __future__ import annotations

import math
from types import MappingProxyType

import numpy as np

from mcbat.checks import check_keys
from mcbat.errors import InputError
from mcbat.study import units as u
from mcbat.study.distributions import parse
from mcbat.study.sections import exactly_one, fixed_number

__all__ = ["CONTACT_QUANTITIES", "INPUT_COLUMNS", "NOISE_OUTPUTS", "VECTORS", "fill_defaults",
           "parse_inputs", "parse_noise"]

# Measurement noise (section [noise]) of output <name> is drawn like a random input
# named "noise.<name>", in the counter domain of noise (never an input's stream).
# Outputs that can get simulated measurement noise, and their quantities. The noisy copy
# goes to a separate column "<name>_measured"; the model value is never altered.
NOISE_OUTPUTS = {"exit_speed": "speed", "scattering_angle": "angle",
                 "spin_axial": "spin", "spin": "spin"}
#: The vector sections: the prefix of their solver columns and their quantity.
VECTORS = {
    "ball_velocity": ("ball_v", u.SPEED),
    "ball_spin": ("ball_w", u.SPIN),
    "bat_velocity": ("bat_v", u.SPEED),
    "bat_spin": ("bat_w", u.SPIN),
}
#: The keys of ``[contact]`` and their quantities.
CONTACT_QUANTITIES = {"axial": u.LENGTH, "from_barrel_end": u.LENGTH, "angle": u.ANGLE,
                      "impact_parameter": u.LENGTH, "approach_azimuth": u.ANGLE}
#: Input -> the solver column it is drawn into.
INPUT_COLUMNS = {
    "contact.axial": "axial", "contact.from_barrel_end": "axial",
    "contact.angle": "angle", "contact.impact_parameter": "impact_parameter",
    "friction.mu": "mu", "restitution.e": "e", "restitution.loss_fraction": "e",
    "restitution.e_x": "e_x",
    **{f"{section}.{axis}": f"{prefix}{axis}_in"
       for section, (prefix, _) in VECTORS.items() for axis in "xyz"},
}


def parse_noise(table):
    """The ``[noise]`` section: standard deviations in SI (the scattering angle's in
    degrees, like its column)."""
    noise = check_keys(table, "noise", (), tuple(NOISE_OUTPUTS))
    out = MappingProxyType({
        name: fixed_number(spec, f"noise.{name}", NOISE_OUTPUTS[name], positive=False)
        * (180.0 / math.pi if name == "scattering_angle" else 1.0)
        for name, spec in noise.items()})
    for name, std in out.items():
        if not std >= 0.0:
            raise InputError(f"noise.{name}", f"must be a standard deviation >= 0, "
                             f"got {std!r}")
    return out


def parse_inputs(data) -> dict:
    """The numeric inputs, in declaration order (sections, then keys, as in the file)."""
    inputs = {}
    for section, table in data.items():
        if section == "contact":
            check_keys(table, "contact", (), tuple(CONTACT_QUANTITIES))
            for key, spec in table.items():
                inputs[f"contact.{key}"] = parse(spec, f"contact.{key}",
                                                 CONTACT_QUANTITIES[key])
        elif section in VECTORS:
            check_keys(table, section, (), ("x", "y", "z"))
            for key, spec in table.items():
                inputs[f"{section}.{key}"] = parse(spec, f"{section}.{key}",
                                                   VECTORS[section][1])
        elif section == "friction":
            check_keys(table, "friction", ("mu",))
            inputs["friction.mu"] = parse(table["mu"], "friction.mu", u.DIMENSIONLESS)
        elif section == "restitution":
            check_keys(table, "restitution", (), ("e", "loss_fraction", "e_x"))
            if "e_x" not in table or "e" in table or "loss_fraction" in table:
                exactly_one(table, "restitution", "e", "loss_fraction")
            for key, spec in table.items():
                inputs[f"restitution.{key}"] = parse(spec, f"restitution.{key}",
                                                     u.DIMENSIONLESS)
    return inputs


def fill_defaults(cols, drawn) -> None:
    """Columns of inputs the study leaves out (zero vectors, ``e* = 1``, ``e_x = 0``), and
    ``e*`` from a drawn loss fraction (in place)."""
    for section, (prefix, _) in VECTORS.items():
        for axis in "xyz":
            if f"{section}.{axis}" not in drawn:
                cols[f"{prefix}{axis}_in"][:] = 0.0
    if "restitution.loss_fraction" in drawn:
        e = cols["e"]
        np.subtract(1.0, e, out=e)
        np.sqrt(e, out=e)
    elif "restitution.e" not in drawn:
        cols["e"][:] = 1.0
    if "restitution.e_x" not in drawn:
        cols["e_x"][:] = 0.0

