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
from mcbat.study.distributions import fixed_value

__all__ = ["GAME_SECTIONS", "HANDEDNESS", "KEYS", "OPTIONAL_SECTIONS", "REQUIRED_SECTIONS",
           "TREND_KEYS", "check_bat_angle_trend", "check_sections", "check_swing_angles",
           "is_game", "largest_magnitude", "parse_handedness", "parse_plate_x_trend",
           "parse_plate_z_trend", "parse_swing_length_trend", "parse_trend"]

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


TREND_KEYS = {"reference": u.SPEED, "per": u.SPEED, "from_barrel_end": u.LENGTH,
              "undercut": u.LENGTH}
PLATE_X_TREND_KEYS = {"reference": u.LENGTH, "dead_zone": u.LENGTH, "per": u.LENGTH,
                      "from_barrel_end": u.LENGTH}
PLATE_Z_TREND_KEYS = {"reference": u.LENGTH, "per": u.LENGTH, "undercut": u.LENGTH,
                      "vertical_bat_angle": u.ANGLE}


def _fixed_table(table, name, keys, example, optional=()) -> dict:
    """The fixed values (SI) of the trend table ``name``: every key of ``keys`` required
    but those of ``optional`` (0 when left out)."""
    if not isinstance(table, dict):
        raise InputError(name, f"must be a table ([{name}]), got {table!r}")
    check_keys(table, name, tuple(k for k in keys if k not in optional), tuple(optional))
    values = {}
    for key, quantity in keys.items():
        if key not in table:
            values[key] = 0.0
            continue
        values[key] = fixed_value(table[key], f"{name}.{key}", quantity, example)
    if not values["per"] > 0.0:
        raise InputError(f"{name}.per", f"must be > 0 (the step the shift is given for), "
                         f"got {table['per']!r}")
    return values


def parse_trend(table):
    """``[contact.bat_speed_trend]`` -> ``(reference bat speed m/s, from_barrel_end's slope
    m per m/s, undercut's slope m per m/s)``, or None without the table. Either shift may
    be left out (no move); one of them must be given."""
    if table is None:
        return None
    name = "contact.bat_speed_trend"
    values = _fixed_table(table, name, TREND_KEYS, '{ value = 10, unit = "mph" }',
                          optional=("from_barrel_end", "undercut"))
    if "from_barrel_end" not in table and "undercut" not in table:
        raise InputError(name, "needs from_barrel_end or undercut (the shift of the contact "
                         "along the bat or under the ball's centre for every `per` of bat "
                         "speed)")
    if not values["reference"] >= 0.0:
        raise InputError(f"{name}.reference", f"must be >= 0, got {table['reference']!r}")
    return (values["reference"], values["from_barrel_end"] / values["per"],
            values["undercut"] / values["per"])


def parse_plate_x_trend(table):
    """``[contact.plate_x_trend]`` -> ``(reference m, dead zone m, slope m per m)``, or
    None without the table."""
    if table is None:
        return None
    values = _fixed_table(table, "contact.plate_x_trend", PLATE_X_TREND_KEYS,
                          '{ value = 6, unit = "in" }')
    if not values["dead_zone"] >= 0.0:
        raise InputError("contact.plate_x_trend.dead_zone", f"must be >= 0 (the half-width "
                         f"over which the contact does not move), got {table['dead_zone']!r}")
    return values["reference"], values["dead_zone"], values["from_barrel_end"] / values["per"]


def parse_plate_z_trend(table):
    """``[contact.plate_z_trend]`` -> ``(reference m, the undercut's slope m per m, the
    vertical bat angle's slope rad per m)``, or None without the table. Either move may be
    left out (0); one of them must be given."""
    if table is None:
        return None
    name = "contact.plate_z_trend"
    values = _fixed_table(table, name, PLATE_Z_TREND_KEYS, '{ value = 1, unit = "ft" }',
                          optional=("undercut", "vertical_bat_angle"))
    if "undercut" not in table and "vertical_bat_angle" not in table:
        raise InputError(name, "needs undercut or vertical_bat_angle (the move of the "
                         "undercut or of the bat's angle for every `per` of pitch height)")
    return (values["reference"], values["undercut"] / values["per"],
            values["vertical_bat_angle"] / values["per"])


def parse_swing_length_trend(table):
    """``[contact.swing_length_trend]`` -> ``(reference m, slope m per m)``, or None
    without the table: the undercut's move with Statcast's ``swing_length``, of the same
    form as the pitch height's."""
    if table is None:
        return None
    name = "contact.swing_length_trend"
    keys = {k: q for k, q in PLATE_Z_TREND_KEYS.items() if k != "vertical_bat_angle"}
    values = _fixed_table(table, name, keys, '{ value = 1, unit = "ft" }')
    return values["reference"], values["undercut"] / values["per"]


def check_bat_angle_trend(trend, vertical_bat_angle) -> None:
    """A ``[contact.plate_z_trend] vertical_bat_angle`` needs ``[swing]
    vertical_bat_angle`` as a distribution, whose range holds the moved angles."""
    if trend is not None and trend[2] != 0.0 and getattr(vertical_bat_angle, "family",
                                                         "fixed") == "fixed":
        raise InputError("contact.plate_z_trend.vertical_bat_angle", "needs [swing] "
                         "vertical_bat_angle as a distribution (the moved angle is held "
                         "inside its range)")


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
