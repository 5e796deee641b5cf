"""The JSON contract of ``mcbat impact`` and ``mcbat flight``: a JSON object -> a case, a
result -> a JSON-ready dict whose ``units`` block names the unit of every quantity.

Inputs are SI unless a value is written ``{"value": ..., "unit": ...}`` (the game's keys,
the flight's); ``docs/impact.md``, ``docs/batting.md`` and ``docs/flight.md`` list the keys.
The answer of ``mcbat impact`` for a game case is itself a ``mcbat flight`` input: its
``units`` block says that its launch numbers are in mph, deg and rpm, and
:func:`flight_case_from_dict` reads them so.

>>> from mcbat.api import solve_game
>>> from mcbat.api.contract import case_from_dict, flight_case_from_dict, game_result_to_dict
>>> game = case_from_dict({"bat": {"preset": "r161"}, "mu": 0.5,
...                        "pitch": {"speed": {"value": 90, "unit": "mph"}},
...                        "swing": {"bat_speed": {"value": 70, "unit": "mph"},
...                                  "attack_angle": {"value": 10, "unit": "deg"}}})
>>> answer = game_result_to_dict(solve_game(game))
>>> answer["units"]["launch_speed"], answer["units"]["backspin"]
('mph', 'rpm')
>>> flight = flight_case_from_dict(answer)              # mph, deg, rpm -> SI
>>> abs(flight.launch_speed - answer["launch_speed"] * 0.44704) < 1e-9
True
"""

from __future__ import annotations

import math

from mcbat.api.flight import FT, FlightCase, FlightResult
from mcbat.api.game import GAME_JSON_KEYS, GameCase, GameResult
from mcbat.api.impact import Contact, ImpactCase, ImpactResult
from mcbat.bodies import BALL_PRESETS, BAT_PRESETS, Ball, Bat, bat_preset
from mcbat.bodies.game import GAME_RESTITUTION, Restitution
from mcbat.dataset.schema import UNITS as COLUMN_UNITS
from mcbat.errors import InputError
from mcbat.errors import check_real as _real
from mcbat.study import units as u
from mcbat.study.distributions import parse
from mcbat.study.flight import FLIGHT_KEYS, parse_flight
from mcbat.study.game import KEYS as GAME_KEYS
from mcbat.study.game import is_game
from mcbat.study.spec import parse_ball

__all__ = ["FLIGHT_UNITS", "GAME_UNITS", "IMPACT_CASE_UNITS", "IMPACT_UNITS", "any_case_from_dict",
           "case_from_dict", "flight_case_from_dict", "flight_result_to_dict",
           "game_case_from_dict", "game_result_to_dict", "impact_case_from_dict",
           "impact_case_to_dict", "impact_result_to_dict"]

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
"""The unit of every quantity of an impact's answer (:func:`impact_result_to_dict`)."""

IMPACT_CASE_UNITS = {
    "ball": {"mass": "kg", "radius": "m", "inertia_factor": "1"},
    "bat": {"mass": "kg", "radius": "m", "transverse_inertia": "kg m^2",
            "axial_inertia": "kg m^2"},
    "contact": {"axial": "m", "angle": "rad"}, **_VECTORS, "mu": "1",
    "restitution": {"e": "1", "e_x": "1"},
}
"""The units of a bat-frame JSON case (:func:`impact_case_to_dict`): SI throughout."""

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
"""The unit of every quantity of a game's answer (:func:`game_result_to_dict`; its
``bat_frame``, an impact's answer, carries its own ``units``)."""

FLIGHT_UNITS = {
    **{k: COLUMN_UNITS[k] for k in ("hit_distance", "hang_time", "apex", "landing_x",
                                    "landing_y", "hit_distance_m", "apex_m", "landing_x_m",
                                    "landing_y_m")},
    "flight_steps": "1",
}
"""The unit of every quantity of a flight's answer (:func:`flight_result_to_dict`)."""
_TRAJECTORY_UNITS = {"t": "s", "x": "m", "y": "m", "z": "m"}

# ---- results -> JSON ----


def impact_result_to_dict(result: ImpactResult) -> dict:
    """An impact's answer (the output contract of ``mcbat impact``, ``docs/impact.md``)."""
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
        "units": IMPACT_UNITS,
    }


def game_result_to_dict(result: GameResult) -> dict:
    """A game's answer (the output of ``mcbat impact`` for a game case): the batted ball
    in Statcast's units (mph, deg, rpm), the field-frame vectors (SI), the bat-frame case
    and its answer. ``mcbat flight`` reads it as it is (:func:`flight_case_from_dict`)."""
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
        "units": GAME_UNITS,
    }


def flight_result_to_dict(result: FlightResult) -> dict:
    """A flight's answer (the output of ``mcbat flight``, ``docs/flight.md``): distances in
    ft as Statcast gives them and in m."""
    out = {"hit_distance": result.hit_distance, "hang_time": result.hang_time,
           "apex": result.apex_m / FT, "landing_x": result.landing_x_m / FT,
           "landing_y": result.landing_y_m / FT, "hit_distance_m": result.hit_distance_m,
           "apex_m": result.apex_m, "landing_x_m": result.landing_x_m,
           "landing_y_m": result.landing_y_m, "flight_steps": result.steps,
           "units": dict(FLIGHT_UNITS)}
    if result.trajectory is not None:
        out["trajectory"] = result.trajectory
        out["units"]["trajectory"] = _TRAJECTORY_UNITS
    return out


# ---- JSON -> cases ----

_CASE_KEYS = {"ball", "bat", "contact", "ball_velocity", "ball_spin", "bat_velocity",
              "bat_spin", "mu", "restitution"}
_REQUIRED = ("ball", "bat", "contact", "ball_velocity", "mu")
def _mapping(data, name, allowed, required):
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


def _build(prefix, builder, *args, **kwargs):
    """``builder(*args, **kwargs)``, with input errors located inside ``prefix``."""
    try:
        return builder(*args, **kwargs)
    except InputError as err:
        raise err.within(prefix) from None


def impact_case_from_dict(data) -> ImpactCase:
    """A bat-frame case of ``mcbat impact`` (``docs/impact.md``; SI), checked against the
    solver's ranges and for bodies approaching at the contact."""
    _mapping(data, "", _CASE_KEYS, _REQUIRED)
    ball_d = _mapping(data["ball"], "ball", {"mass", "radius", "inertia_factor"},
                      ("mass", "radius"))
    ball = _build("ball", Ball, **ball_d)
    if isinstance(data["bat"], dict) and "preset" in data["bat"]:
        bat = _build("bat", _bat_from_dict, data["bat"])
    else:
        bat_d = _mapping(data["bat"], "bat",
                         {"mass", "radius", "transverse_inertia", "axial_inertia"},
                         ("mass", "radius", "transverse_inertia", "axial_inertia"))
        bat = _build("bat", Bat, **bat_d)
    contact_d = _mapping(data["contact"], "contact",
                         {"axial", "angle", "impact_parameter", "approach_azimuth"}, ("axial",))
    if ("angle" in contact_d) == ("impact_parameter" in contact_d):
        raise InputError("contact", "give exactly one of 'angle' or 'impact_parameter'")
    if "angle" in contact_d:
        if "approach_azimuth" in contact_d:
            raise InputError("contact.approach_azimuth", "only valid with 'impact_parameter'")
        contact = _build("contact", Contact, **contact_d)
    else:
        axial = _build("contact", _real, contact_d["axial"], "axial")
        contact = _build("contact", Contact.from_impact_parameter, axial=axial,
                         impact_parameter=contact_d["impact_parameter"], ball=ball, bat=bat,
                         approach_azimuth=contact_d.get("approach_azimuth", 0.0))
    e, e_x = 1.0, 0.0
    if "restitution" in data:
        rest = dict(_mapping(data["restitution"], "restitution",
                             {"e", "loss_fraction", "e_x"}, ()))
        if "e_x" in rest:  # tangential restitution (optional; alone it keeps e* = 1)
            e_x = _build("restitution", _real, rest.pop("e_x"), "e_x", minimum=0.0,
                         maximum=1.0)
        elif len(rest) != 1:
            raise InputError("restitution", "give exactly one of 'e' or 'loss_fraction'")
        if len(rest) > 1:
            raise InputError("restitution", "give exactly one of 'e' or 'loss_fraction'")
        if "e" in rest:
            e = _build("restitution", _real, rest["e"], "e", minimum=0.0, maximum=1.0)
        elif "loss_fraction" in rest:
            e = _build("restitution", ImpactCase.e_from_loss_fraction,
                       loss_fraction=rest["loss_fraction"])
    vectors = {k: data[k] for k in ("ball_velocity", "ball_spin", "bat_velocity", "bat_spin")
               if k in data}
    case = ImpactCase(ball=ball, bat=bat, contact=contact, mu=data["mu"], e=e, e_x=e_x,
                        **vectors)
    case.check_solver_ranges()
    case.validate_approach()
    return case




def impact_case_to_dict(case: ImpactCase) -> dict:
    """An :class:`ImpactCase` as a bat-frame JSON case of ``mcbat impact`` (SI units,
    :data:`IMPACT_CASE_UNITS`)."""
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


def _game_value(spec, field, quantity):
    return parse(spec, field, quantity, kinds=("fixed",)).value


def game_case_from_dict(data) -> GameCase:
    """A game case of ``mcbat impact`` (``docs/batting.md``): numbers in SI or as
    ``{"value": ..., "unit": ...}``; errors name the JSON keys (``pitch.speed``)."""
    allowed = {"handedness", "ball", "bat", "pitch", "swing", "contact", "mu", "restitution"}
    _mapping(data, "", allowed, ("bat", "pitch", "swing", "mu"))
    ball = (BALL_PRESETS["baseball"] if "ball" not in data
            else _build("ball", _ball_from_dict, data["ball"]))
    bat = _build("bat", _bat_from_dict, data["bat"], game=True)
    values = {}
    for section in ("pitch", "swing", "contact"):
        keys = GAME_KEYS[section]
        table = _mapping(data.get(section, {}), section, set(keys),
                         [k for k, spec in keys.items() if spec[1] is None])
        for key, spec in table.items():
            values[keys[key][2].removeprefix("pitch_") if section == "pitch" else
                   keys[key][2]] = _game_value(spec, f"{section}.{key}", keys[key][0])
    values["pitch_speed"] = values.pop("speed")
    mu = _game_value(data["mu"], "mu", "dimensionless")
    restitution = GAME_RESTITUTION
    if "restitution" in data:
        keys = GAME_KEYS["restitution"]
        rest = _mapping(data["restitution"], "restitution", set(keys) | {"location"}, ())
        if ("e" in rest) == ("e_ref" in rest):
            raise InputError("restitution", "give exactly one of 'e' (a constant e*) or "
                             "'e_ref' (with e_slope and e_speed_ref)")
        kw = {("e_ref" if k == "e" else k): (_game_value(v, f"restitution.{k}", keys[k][0])
                                             if k != "location" else v)
              for k, v in rest.items()}
        restitution = _build("restitution", Restitution, **kw)
    handedness = data.get("handedness", "R")
    try:
        return GameCase(ball=ball, bat=bat, mu=mu, handedness=handedness,
                        restitution=restitution, **values)
    except InputError as err:
        if err.field in GAME_JSON_KEYS:
            section, key = GAME_JSON_KEYS[err.field]
            raise InputError(f"{section}.{key}", err.message) from None
        raise


def _ball_from_dict(data) -> Ball:
    if isinstance(data, dict) and "preset" in data:
        _mapping(data, "", {"preset"}, ())
        if data["preset"] not in BALL_PRESETS:
            raise InputError("preset", f"unknown ball preset {data['preset']!r}")
        return BALL_PRESETS[data["preset"]]
    _mapping(data, "", {"mass", "radius", "inertia_factor"}, ("mass", "radius"))
    return Ball(**data)


def _bat_from_dict(data, game=False) -> Bat:
    """A bat from ``{"preset": name}`` or a cylinder's values (a game bat also needs
    ``length`` and ``cm_from_knob``)."""
    if isinstance(data, dict) and "preset" in data:
        _mapping(data, "", {"preset"}, ())
        if data["preset"] not in BAT_PRESETS:
            raise InputError("preset", f"unknown bat preset {data['preset']!r} (expected one "
                             f"of: {', '.join(BAT_PRESETS)})")
        return bat_preset(data["preset"])
    keys = {"mass", "radius", "transverse_inertia", "axial_inertia"}
    required = ["mass", "radius", "transverse_inertia", "axial_inertia"]
    if game:
        keys |= {"length", "cm_from_knob"}
        required += ["length", "cm_from_knob"]
    _mapping(data, "", keys, required)
    values = {k: _game_value(v, k, _BAT_QUANTITIES[k]) for k, v in data.items()}
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


def case_from_dict(data):
    """A :class:`GameCase` for a JSON case with ``pitch``/``swing`` keys, else an
    :class:`ImpactCase`."""
    return game_case_from_dict(data) if is_game(data) else impact_case_from_dict(data)


def any_case_from_dict(data):
    """The case of any JSON object ``mcbat impact`` or ``mcbat flight`` reads: a
    :class:`FlightCase` for one with ``launch_speed`` (a game's answer among them), else
    :func:`case_from_dict`."""
    if isinstance(data, dict) and not is_game(data) and ("launch_speed" in data
                                                         or "bat_frame" in data):
        return flight_case_from_dict(data)
    return case_from_dict(data)


_LAUNCH_KEYS = {"launch_speed": (u.SPEED, None), "launch_angle": (u.ANGLE, None),
                "spray_angle": (u.ANGLE, 0.0), "backspin": (u.SPIN, 0.0),
                "sidespin": (u.SPIN, 0.0), "gyrospin": (u.SPIN, 0.0)}
#: The keys of a game's answer that a flight does not read (its ball comes from
#: ``bat_frame_case.ball``).
_GAME_ANSWER_KEYS = {"status", "end_state", "spin_rate", "collision_efficiency", "field",
                     "bat_frame_case", "bat_frame"}


def _launch_units(data, game_answer) -> dict:
    """The ``units`` block of a flight's input: the unit of each plain-number launch key."""
    if "units" not in data:
        if game_answer:
            raise InputError("units", "missing: the answer of a game gives launch_speed, "
                             "launch_angle and the spins in mph, deg and rpm, and its units "
                             "block says so; keep it (or write each value as "
                             "{value, unit})")
        return {}
    units = data["units"]
    if not isinstance(units, dict):
        raise InputError("units", f"must be an object, got {type(units).__name__}")
    out = {}
    for key, unit in units.items():
        if key in _LAUNCH_KEYS:
            u.factor(unit, _LAUNCH_KEYS[key][0], f"units.{key}")  # validates the unit
            out[key] = unit
        elif not (game_answer and key in _GAME_ANSWER_KEYS):
            raise InputError(f"units.{key}", "a units block names the units of the launch "
                             f"numbers only ({', '.join(_LAUNCH_KEYS)}); write other values "
                             "as {value, unit}")
    return out


def flight_case_from_dict(data) -> FlightCase:
    """A :class:`FlightCase` from a ``mcbat flight`` JSON object: values in SI, or as
    ``{"value": ..., "unit": ...}``, or plain numbers in the units a ``units`` block names
    (``{"launch_speed": "mph", ...}``).

    The answer of ``mcbat impact`` for a game case is such an object: its launch numbers
    are read in its units (mph, deg, rpm), its ball is the game's (``bat_frame_case.ball``,
    unless ``ball`` is given), its other keys are ignored.

    Raises
    ------
    InputError
        Naming the key.
    """
    game_answer = isinstance(data, dict) and "bat_frame" in data
    allowed = set(_LAUNCH_KEYS) | {"ball", "units"} | set(FLIGHT_KEYS)
    _mapping(data, "", allowed | (_GAME_ANSWER_KEYS if game_answer else set()),
             ("launch_speed", "launch_angle"))
    if game_answer and data.get("status", "ok") != "ok":
        raise InputError("status", f"the game was not solved (status {data['status']!r})")
    units = _launch_units(data, game_answer)
    launch = {}
    for key, (quantity, default) in _LAUNCH_KEYS.items():
        spec = data.get(key, default)
        if key in units and not isinstance(spec, dict):
            spec = {"value": spec, "unit": units[key]}
        value = _game_value(spec, key, quantity) if key in data else default
        if not math.isfinite(value):
            raise InputError(key, f"must be a finite number, got {data[key]!r}")
        launch[key] = value
    if not launch["launch_speed"] > 0.0:
        raise InputError("launch_speed", f"must be > 0, got {data['launch_speed']!r}")
    if not abs(launch["launch_angle"]) <= math.pi / 2:
        raise InputError("launch_angle", f"must be within [-90, 90] deg, got "
                         f"{data['launch_angle']!r}"
                         f"{' ' + units['launch_angle'] if 'launch_angle' in units else ''}")
    if "ball" in data:
        ball = parse_ball(data["ball"])
    elif game_answer:
        case = data.get("bat_frame_case")
        if not isinstance(case, dict) or "ball" not in case:
            raise InputError("bat_frame_case.ball", "missing: a game's answer names its ball "
                             "there (or give 'ball')")
        ball = _build("bat_frame_case", parse_ball, case["ball"])
    else:
        ball = BALL_PRESETS["baseball"]
    settings = parse_flight({k: v for k, v in data.items() if k in FLIGHT_KEYS}, field="")
    return FlightCase(ball=ball, settings=settings, **launch)
