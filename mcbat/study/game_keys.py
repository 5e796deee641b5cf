"""The keys of a game study or case: its sections, its numeric keys with their units and
defaults, and the checks that need more than one key (``mcbat.study.game``; the format:
``docs/batting.md``)."""

from __future__ import annotations

import math

from mcbat.bodies.swing import DEFAULT_PIVOT
from mcbat.checks import check_keys
from mcbat.errors import InputError
from mcbat.solving.names import SWEET_SPOT_FROM_BARREL_END
from mcbat.study import units as u
from mcbat.study.distributions import parse

__all__ = ["GAME_SECTIONS", "HANDEDNESS", "KEYS", "OPTIONAL_SECTIONS", "REQUIRED_SECTIONS",
           "TREND_KEYS", "check_sections", "check_swing_angles", "is_game",
           "largest_magnitude", "parse_handedness", "parse_trend"]

#: The numeric keys of a game: section -> key -> (quantity, default in SI, column).
KEYS = {
    "pitch": {
        "speed": (u.SPEED, None, "pitch_speed"),
        "vertical_approach_angle": (u.ANGLE, 0.0, "pitch_vertical_approach_angle"),
        "horizontal_approach_angle": (u.ANGLE, 0.0, "pitch_horizontal_approach_angle"),
        "spin_rate": (u.SPIN, 0.0, "pitch_spin_rate"),
        "spin_axis": (u.ANGLE, math.pi, "pitch_spin_axis"),
        "spin_efficiency": (u.DIMENSIONLESS, 1.0, "pitch_spin_efficiency"),
        "gyro_sign": (u.DIMENSIONLESS, 1.0, "pitch_gyro_sign"),
    },
    "swing": {
        "bat_speed": (u.SPEED, None, "bat_speed"),
        "attack_angle": (u.ANGLE, 0.0, "attack_angle"),
        "attack_direction": (u.ANGLE, 0.0, "attack_direction"),
        "vertical_bat_angle": (u.ANGLE, 0.0, "vertical_bat_angle"),
        "pivot": (u.LENGTH, DEFAULT_PIVOT, "pivot"),
    },
    "contact": {
        "from_barrel_end": (u.LENGTH, SWEET_SPOT_FROM_BARREL_END, "from_barrel_end"),
        "undercut": (u.LENGTH, 0.0, "undercut"),
    },
    "friction": {"mu": (u.DIMENSIONLESS, None, "mu")},
    "restitution": {
        "e": (u.DIMENSIONLESS, None, "e_ref"),
        "e_ref": (u.DIMENSIONLESS, None, "e_ref"),
        "e_slope": (u.DIMENSIONLESS, 0.0, "e_slope"),
        "e_speed_ref": (u.SPEED, 0.0, "e_speed_ref"),
        "e_x": (u.DIMENSIONLESS, 0.0, "e_x"),
    },
}
GAME_SECTIONS = ("pitch", "swing")
REQUIRED_SECTIONS = ("study", "ball", "bat", "pitch", "swing", "friction")
OPTIONAL_SECTIONS = ("handedness", "contact", "restitution", "solver", "flight", "output",
                     "summary", "pitches")
HANDEDNESS = {"R": 1.0, "L": -1.0}
_RAD = 180.0 / math.pi


def is_game(data) -> bool:
    """True for a study or case with a ``pitch`` or ``swing`` section."""
    return isinstance(data, dict) and any(k in data for k in GAME_SECTIONS)


def parse_handedness(value, field="handedness") -> float:
    """``"R"`` -> +1, ``"L"`` -> -1."""
    if not isinstance(value, str) or value not in HANDEDNESS:
        raise InputError(field, f'must be "R" or "L", got {value!r}')
    return HANDEDNESS[value]


def check_swing_angles(attack_angle, vertical_bat_angle, field="swing.vertical_bat_angle"):
    """The bat axis must be perpendicular to the sweet spot's velocity:
    ``|tan(attack_angle) tan(vertical_bat_angle)| < 1`` (largest magnitudes, rad)."""
    product = abs(math.tan(attack_angle) * math.tan(vertical_bat_angle))
    if not product < 1.0 - 1e-9:
        raise InputError(field, f"inconsistent with swing.attack_angle: no bat axis has "
                         f"elevation {vertical_bat_angle * _RAD:.4g} deg and is "
                         f"perpendicular to a sweet-spot velocity {attack_angle * _RAD:.4g} "
                         f"deg above the horizontal (need |tan(attack) tan(vertical)| < 1, "
                         f"got {product:.4g})")


TREND_KEYS = {"reference": u.SPEED, "per": u.SPEED, "from_barrel_end": u.LENGTH}


def parse_trend(table):
    """``[contact.bat_speed_trend]`` -> ``(reference bat speed m/s, slope m per m/s)``, or
    None without the table."""
    if table is None:
        return None
    if not isinstance(table, dict):
        raise InputError("contact.bat_speed_trend", f"must be a table "
                         f"([contact.bat_speed_trend]), got {table!r}")
    check_keys(table, "contact.bat_speed_trend", tuple(TREND_KEYS), ())
    values = {}
    for key, quantity in TREND_KEYS.items():
        name = f"contact.bat_speed_trend.{key}"
        dist = parse(table[key], name, quantity)
        if dist.family != "fixed" or not math.isfinite(dist.value):
            raise InputError(name, f"must be a fixed value (e.g. {{ value = 10, unit = "
                             f"\"mph\" }}), got {table[key]!r}")
        values[key] = float(dist.value)
    if not values["per"] > 0.0:
        raise InputError("contact.bat_speed_trend.per", f"must be > 0 (the bat-speed step "
                         f"the shift is given for), got {table['per']!r}")
    if not values["reference"] >= 0.0:
        raise InputError("contact.bat_speed_trend.reference", f"must be >= 0, got "
                         f"{table['reference']!r}")
    return values["reference"], values["from_barrel_end"] / values["per"]


def largest_magnitude(dist):
    """The largest magnitude a distribution draws (SI)."""
    low, high = dist.support()
    return max(abs(low), abs(high))


def check_sections(data):
    """Known sections, tables where tables belong, the required ones present."""
    check_keys(data, "", (), REQUIRED_SECTIONS + OPTIONAL_SECTIONS)
    for section in data:
        if section != "handedness" and not isinstance(data[section], dict):
            raise InputError(section, f"must be a table ([{section}]), "
                                      f"got {data[section]!r}")
    for section in REQUIRED_SECTIONS:
        # (with real pitches, [pitch] and [swing] may be left out: their other keys have
        # defaults)
        if section not in data and not ("pitches" in data and section in GAME_SECTIONS):
            raise InputError(section, f"missing required section [{section}]")
