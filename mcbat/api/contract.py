"""The JSON contract of ``mcbat impact`` and ``mcbat flight``, shared by the case types:
the units of every answer, the answers themselves (a result -> a JSON-ready dict whose
``units`` block names the unit of every quantity), the unit of a bare number in each key
(``FIELD_KEYS``, ``field_value``), and the readers of the parts the JSON cases
share (``{"value": ..., "unit": ...}`` numbers, balls, bats, key checks).

**Bare numbers.** In the keys of a game case and a flight case that the field measures
(``FIELD_KEYS``: speeds, angles, spins, distances on the field, the weather), a bare
number is read in the field's unit, the one the JSON answers use: mph, deg, rpm, ft (and
degF, inHg for the air); a bare number outside the key's plausible range in that unit is
refused, naming the key, the unit and the range. Everywhere else (a bat-frame case, the
bat, the ball, the contact point, the restitution) a bare number is SI. ``{"value": ...,
"unit": ...}`` gives any value in any unit of its quantity.

Each case type reads its own JSON with these (``mcbat.api.impact.impact_case_from_dict``,
``mcbat.api.game.game_case_from_dict``, ``mcbat.api.flight.flight_case_from_dict``;
``mcbat.api.case_from_dict`` picks one), and its result's ``to_dict()`` is the answer
written here. This module imports none of them: the types build on the contract, never
the other way round.

>>> import mcbat
>>> from mcbat.api import case_from_dict, flight_case_from_dict
>>> game = case_from_dict({"bat": {"preset": "r161"}, "mu": 0.5,
...                        "pitch": {"speed": {"value": 90, "unit": "mph"}},
...                        "swing": {"bat_speed": {"value": 70, "unit": "mph"},
...                                  "attack_angle": {"value": 10, "unit": "deg"}}})
>>> answer = game_result_to_dict(mcbat.solve(game))
>>> answer["units"]["launch_speed"], answer["units"]["backspin"]
('mph', 'rpm')
>>> flight = flight_case_from_dict(answer)              # mph, deg, rpm -> SI
>>> from mcbat.core.units import M_S_PER_MPH
>>> abs(flight.launch_speed - answer["launch_speed"] * M_S_PER_MPH) < 1e-9
True
>>> field_value(94, "pitch.speed")                      # a bare number: mph
42.02176
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Iterable
from typing import Any, ParamSpec, TypeVar, cast

from mcbat.bodies import BALL_PRESETS, BAT_PRESETS, Ball, Bat, bat_preset
from mcbat.core.units import M_PER_FT as FT
from mcbat.dataset.schema import UNITS as COLUMN_UNITS
from mcbat.errors import InputError
from mcbat.study import units as u
from mcbat.study.dist_types import Fixed
from mcbat.study.distributions import parse

_P = ParamSpec("_P")
_T = TypeVar("_T")

__all__ = ["FIELD_KEYS", "FLIGHT_UNITS", "FT", "GAME_UNITS", "IMPACT_CASE_UNITS",
           "IMPACT_UNITS", "ball_from_dict", "bat_from_dict", "check_object", "field_spec",
           "field_value", "fixed_value", "flight_result_to_dict", "game_result_to_dict",
           "impact_case_to_dict", "impact_result_to_dict", "located"]

# ---- units: the dataset schema's, for the quantities the answers share with datasets ----

_VECTORS = {"ball_velocity": COLUMN_UNITS["ball_vx"], "ball_spin": COLUMN_UNITS["ball_wx"],
            "bat_velocity": COLUMN_UNITS["bat_vx"], "bat_spin": COLUMN_UNITS["bat_wx"]}

IMPACT_UNITS = {
    **_VECTORS,
    **{k: COLUMN_UNITS[k] for k in ("normal_impulse", "stick_impulse", "compression_impulse")},
    "tangential_impulse": COLUMN_UNITS["tangential_impulse_1"],
    **{k: COLUMN_UNITS[k] for k in ("compression_work", "normal_work", "friction_work")},
    "restitution_loss": COLUMN_UNITS["normal_work"],
    **{k: COLUMN_UNITS[k] for k in ("energy_in", "energy_out", "stick_criterion", "exit_speed",
                                    "scattering_angle", "impact_parameter", "rk4_steps")},
}
"""The unit of every quantity of an impact's answer (``impact_result_to_dict``)."""

IMPACT_CASE_UNITS = {
    "ball": {"mass": "kg", "radius": "m", "inertia_factor": "1"},
    "bat": {"mass": "kg", "radius": "m", "transverse_inertia": "kg m^2",
            "axial_inertia": "kg m^2"},
    "contact": {"axial": "m", "angle": "rad"}, **_VECTORS, "mu": "1",
    "restitution": {"e": "1", "e_x": "1"},
}
"""The units of a bat-frame JSON case (``impact_case_to_dict``): SI throughout."""

GAME_UNITS = {
    **{k: COLUMN_UNITS[k] for k in ("launch_speed", "launch_angle", "spray_angle",
                                    "spin_rate", "backspin", "sidespin", "gyrospin",
                                    "collision_efficiency")},
    "field": {**_VECTORS, "pitch_velocity": COLUMN_UNITS["field_ball_vx_in"],
              "pitch_spin": COLUMN_UNITS["field_ball_wx_in"],
              "bat_velocity_in": COLUMN_UNITS["field_bat_vx_in"],
              "bat_spin_in": COLUMN_UNITS["field_bat_wx_in"]},
    "bat_frame_case": IMPACT_CASE_UNITS,
}
"""The unit of every quantity of a game's answer (``game_result_to_dict``; its
``bat_frame``, an impact's answer, carries its own ``units``)."""

FLIGHT_UNITS = {
    **{k: COLUMN_UNITS[k] for k in ("hit_distance", "hang_time", "apex", "landing_x",
                                    "landing_y", "hit_distance_m", "apex_m", "landing_x_m",
                                    "landing_y_m")},
    "flight_steps": "1",
}
"""The unit of every quantity of a flight's answer (``flight_result_to_dict``)."""
# (each answer gets its own copy of these tables: a caller may edit an answer)
_TRAJECTORY_UNITS = {"t": "s", "x": "m", "y": "m", "z": "m"}

# ---- results -> JSON ----


def impact_result_to_dict(result: Any) -> dict[str, Any]:
    """An impact's answer, the output contract of ``mcbat impact`` (``docs/impact.md``).
    The results are typed ``Any`` here: their classes import this module, not the other
    way round."""
    return {
        "status": result.status,
        "end_state": result.end_state,
        "ball_velocity": list(result.ball_velocity),
        "ball_spin": list(result.ball_spin),
        "bat_velocity": list(result.bat_velocity),
        "bat_spin": list(result.bat_spin),
        "normal_impulse": result.normal_impulse,
        "stick_impulse": result.stick_impulse,
        "compression_impulse": result.compression_impulse,
        "tangential_impulse": list(result.tangential_impulse),
        "compression_work": result.compression_work,
        "normal_work": result.normal_work,
        "friction_work": result.friction_work,
        "restitution_loss": result.restitution_loss,
        "energy_in": result.energy_in,
        "energy_out": result.energy_out,
        "stick_criterion": result.stick_criterion,
        "exit_speed": result.exit_speed,
        "scattering_angle": result.scattering_angle,
        "impact_parameter": result.case.impact_parameter(),
        "rk4_steps": result.rk4_steps,
        "units": copy.deepcopy(IMPACT_UNITS),
    }


def game_result_to_dict(result: Any) -> dict[str, Any]:
    """A game's answer (the output of ``mcbat impact`` for a game case): the batted ball
    in Statcast's units (mph, deg, rpm), the field-frame vectors (SI), the bat-frame case
    and its answer. ``mcbat flight`` reads it as it is
    (``mcbat.api.flight.flight_case_from_dict``)."""
    return {
        "status": result.impact.status, "end_state": result.impact.end_state,
        **result.batted_ball,
        "collision_efficiency": result.collision_efficiency,
        "field": {"ball_velocity": list(result.ball_velocity),
                  "ball_spin": list(result.ball_spin),
                  "bat_velocity": list(result.bat_velocity),
                  "bat_spin": list(result.bat_spin),
                  "pitch_velocity": list(result.pitch_velocity),
                  "pitch_spin": list(result.pitch_spin),
                  "bat_velocity_in": list(result.bat_velocity_in),
                  "bat_spin_in": list(result.bat_spin_in)},
        "bat_frame_case": impact_case_to_dict(result.impact.case),
        "bat_frame": impact_result_to_dict(result.impact),
        "units": copy.deepcopy(GAME_UNITS),
    }


def flight_result_to_dict(result: Any) -> dict[str, Any]:
    """A flight's answer (the output of ``mcbat flight``, ``docs/flight.md``): distances in
    ft as Statcast gives them and in m."""
    out: dict[str, Any] = {"hit_distance": result.hit_distance, "hang_time": result.hang_time,
           "apex": result.apex_m / FT, "landing_x": result.landing_x_m / FT,
           "landing_y": result.landing_y_m / FT, "hit_distance_m": result.hit_distance_m,
           "apex_m": result.apex_m, "landing_x_m": result.landing_x_m,
           "landing_y_m": result.landing_y_m, "flight_steps": result.steps,
           "units": copy.deepcopy(FLIGHT_UNITS)}
    if result.trajectory is not None:
        out["trajectory"] = result.trajectory
        out["units"]["trajectory"] = dict(_TRAJECTORY_UNITS)
    return out


def impact_case_to_dict(case: Any) -> dict[str, Any]:
    """An ``ImpactCase`` as a bat-frame JSON case of ``mcbat impact`` (SI units,
    ``IMPACT_CASE_UNITS``)."""
    bat = case.bat
    bat_d = ({"preset": bat.preset} if bat.profile is not None else
             {"mass": bat.mass, "radius": bat.radius,
              "transverse_inertia": bat.transverse_inertia,
              "axial_inertia": bat.axial_inertia})
    return {"ball": {"mass": case.ball.mass, "radius": case.ball.radius,
                     "inertia_factor": case.ball.inertia_factor},
            "bat": bat_d, "contact": {"axial": case.contact.axial, "angle": case.contact.angle},
            "ball_velocity": list(case.ball_velocity), "ball_spin": list(case.ball_spin),
            "bat_velocity": list(case.bat_velocity), "bat_spin": list(case.bat_spin),
            "mu": case.mu, "restitution": {"e": case.e, "e_x": case.e_x}}


# ---- bare numbers: the field's units ----

FIELD_KEYS = {
    # a game case
    "pitch.speed": ("mph", u.SPEED, (25.0, 110.0)),
    "pitch.release_speed": ("mph", u.SPEED, (25.0, 110.0)),
    "pitch.extension": ("ft", u.LENGTH, (3.0, 9.0)),
    "pitch.vertical_approach_angle": ("deg", u.ANGLE, (-45.0, 45.0)),
    "pitch.horizontal_approach_angle": ("deg", u.ANGLE, (-45.0, 45.0)),
    "pitch.spin_rate": ("rpm", u.SPIN, (0.0, 4500.0)),
    "pitch.spin_axis": ("deg", u.ANGLE, (0.0, 360.0)),
    "swing.bat_speed": ("mph", u.SPEED, (0.0, 100.0)),
    "swing.attack_angle": ("deg", u.ANGLE, (-60.0, 60.0)),
    "swing.attack_direction": ("deg", u.ANGLE, (-90.0, 90.0)),
    "swing.vertical_bat_angle": ("deg", u.ANGLE, (-90.0, 90.0)),
    # a flight case (and a game's answer read as one)
    "launch_speed": ("mph", u.SPEED, (0.0, 130.0)),
    "launch_angle": ("deg", u.ANGLE, (-90.0, 90.0)),
    "spray_angle": ("deg", u.ANGLE, (-180.0, 180.0)),
    "backspin": ("rpm", u.SPIN, (-10000.0, 10000.0)),
    "sidespin": ("rpm", u.SPIN, (-10000.0, 10000.0)),
    "gyrospin": ("rpm", u.SPIN, (-10000.0, 10000.0)),
    "position": ("ft", u.LENGTH, (-200.0, 200.0)),
    "wind": ("mph", u.SPEED, (-100.0, 100.0)),
    "landing_height": ("ft", u.LENGTH, (0.0, 30.0)),
    "atmosphere.temperature": ("degF", u.TEMPERATURE, (-20.0, 130.0)),
    "atmosphere.pressure": ("inHg", u.PRESSURE, (25.0, 33.0)),
    "atmosphere.elevation": ("ft", u.LENGTH, (-1500.0, 15000.0)),
}
"""The unit a bare number is read in, key by key, in a game case and a flight case of
``mcbat impact``, ``mcbat flight`` and ``mcbat.solve``: ``key -> (unit, quantity,
(low, high) in that unit)``, the range a bare number must lie within (the field's
values, with room: a number outside it was written in another unit). The units are the
field's, those of the JSON answers (mph, deg, rpm, ft; degF and inHg for the air, as
Nathan's calculator takes them). Keys not listed here read a bare number in SI."""

# The unit suggested for a value the field's unit does not fit.
_OTHER_UNIT = {u.SPEED: "m/s", u.ANGLE: "rad", u.SPIN: "rad/s", u.LENGTH: "m",
               u.TEMPERATURE: "K", u.PRESSURE: "hPa"}


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def field_spec(spec: Any, key: str) -> Any:
    """``spec`` with the unit of a bare number made explicit: a number (or a list of
    numbers, a vector) becomes ``{"value": ..., "unit": <the field's unit>}`` once it is
    found within the key's plausible range (``FIELD_KEYS``); anything else is
    returned as it is, for its reader to check. The one place the rule is applied.

    Raises
    ------
    InputError
        Naming ``key``, the unit assumed and the range, for a bare number outside it.
    """
    if key not in FIELD_KEYS:
        return spec
    unit, quantity, (low, high) = FIELD_KEYS[key]
    numbers = spec if isinstance(spec, list) else [spec]
    if not numbers or not all(_is_number(x) for x in numbers):
        return spec
    for x in numbers:
        try:
            value, shown = float(x), repr(x)
        except OverflowError:  # an integer beyond any float: far outside the range too
            value, shown = high * 2.0 + 1.0, f"a number of {len(str(abs(x)))} digits"
        if math.isfinite(value) and not low <= value <= high:
            raise InputError(key, f"a bare number here is in {unit}, and {shown} {unit} lies "
                             f"outside [{low:g}, {high:g}] {unit}; for another unit write "
                             f'{{"value": ..., "unit": "{_OTHER_UNIT[quantity]}"}}')
    return {"value": spec, "unit": unit}


def field_value(spec: Any, key: str, quantity: str | None = None) -> float:
    """A game or flight key's value in SI: a bare number in the field's unit
    (``field_spec``), or ``{"value": ..., "unit": ...}``. A key not in
    ``FIELD_KEYS`` (``quantity`` needed) reads a bare number in SI."""
    if key in FIELD_KEYS:
        quantity = FIELD_KEYS[key][1]
    return fixed_value(field_spec(spec, key), key, quantity)


# ---- readers of the parts the JSON cases share ----


def check_object(data: Any, name: str, allowed: Iterable[str],
                 required: Iterable[str]) -> dict[str, Any]:
    """``data`` if it is a JSON object with only ``allowed`` keys and every ``required``
    one, else ``InputError`` naming ``name`` or the key."""
    if not isinstance(data, dict):
        raise InputError(name, f"must be an object, got {type(data).__name__}")
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        where = f"{name}." if name else ""
        raise InputError(f"{where}{unknown[0]}",
                         f"unknown key (expected one of: {', '.join(sorted(allowed))})")
    for key in required:
        if key not in data:
            where = f"{name}." if name else ""
            raise InputError(f"{where}{key}", "missing required key")
    return data


def located(prefix: str, builder: Callable[_P, _T], *args: _P.args,
            **kwargs: _P.kwargs) -> _T:
    """``builder(*args, **kwargs)``, with input errors located inside ``prefix``."""
    try:
        return builder(*args, **kwargs)
    except InputError as err:
        raise err.within(prefix) from None


def fixed_value(spec: Any, field: str, quantity: str | None) -> float:
    """A number in SI, or ``{"value": ..., "unit": ...}`` converted to SI (a ``quantity`` of
    ``mcbat.study.units``)."""
    fixed = cast(Fixed, parse(spec, field, quantity, kinds=("fixed",)))  # kinds: a Fixed
    return fixed.value


def ball_from_dict(data: Any) -> Ball:
    """A ball from ``{"preset": name}`` or ``{"mass", "radius"[, "inertia_factor"]}``."""
    if isinstance(data, dict) and "preset" in data:
        check_object(data, "", {"preset"}, ())
        if data["preset"] not in BALL_PRESETS:
            raise InputError("preset", f"unknown ball preset {data['preset']!r}")
        return BALL_PRESETS[data["preset"]]
    check_object(data, "", {"mass", "radius", "inertia_factor"}, ("mass", "radius"))
    return Ball(**data)


def bat_from_dict(data: Any, game: bool = False) -> Bat:
    """A bat from ``{"preset": name}`` or a cylinder's values (a game bat also needs
    ``length`` and ``cm_from_knob``)."""
    if isinstance(data, dict) and "preset" in data:
        check_object(data, "", {"preset"}, ())
        if data["preset"] not in BAT_PRESETS:
            raise InputError("preset", f"unknown bat preset {data['preset']!r} (expected one "
                             f"of: {', '.join(BAT_PRESETS)})")
        return bat_preset(data["preset"])
    keys = {"mass", "radius", "transverse_inertia", "axial_inertia"}
    required = ["mass", "radius", "transverse_inertia", "axial_inertia"]
    if game:
        keys |= {"length", "cm_from_knob"}
        required += ["length", "cm_from_knob"]
    check_object(data, "", keys, required)
    values: dict[str, Any] = {k: fixed_value(v, k, _BAT_QUANTITIES[k]) for k, v in data.items()}
    if game:
        length = values["length"]
        cm = values.pop("cm_from_knob")
        if not 0.0 <= cm <= length:
            raise InputError("cm_from_knob", f"must lie on the bat, within [0, {length:.6g}] "
                             f"m, got {cm!r}")
        values["cm_from_barrel_end"] = length - cm
    return Bat(**values)


_BAT_QUANTITIES = {"mass": "mass", "radius": "length", "transverse_inertia": "inertia",
                   "axial_inertia": "inertia", "length": "length", "cm_from_knob": "length"}
