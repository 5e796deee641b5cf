"""One game situation: a pitch, a swing and a contact in the field frame -> the batted ball.

``GameCase`` takes plain numbers in SI units (m/s, rad, rad/s, m); its result,
``GameResult``, reports the batted ball as Statcast does (mph, deg, rpm). The flight of
that ball: ``mcbat.api.FlightCase.from_result`` converts them (``docs/flight.md``).

Example
-------
>>> import math
>>> from mcbat.api import GameCase, solve_game
>>> from mcbat.bodies import BALL_PRESETS, bat_preset
>>> case = GameCase(ball=BALL_PRESETS["baseball"], bat=bat_preset("r161"),
...                 pitch_speed=40.0, bat_speed=31.0, mu=0.5,
...                 vertical_approach_angle=math.radians(-6.0),
...                 attack_angle=math.radians(10.0), spin_rate=240.0)
>>> result = solve_game(case)
>>> 90 < result.launch_speed < 120        # mph
True
>>> result.to_dict()["units"]["launch_speed"]
'mph'
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from mcbat.api.contract import (
    ball_from_dict,
    bat_from_dict,
    check_object,
    field_value,
    fixed_value,
    game_result_to_dict,
    located,
)
from mcbat.api.impact import Contact, ImpactCase, ImpactResult, SolverSettings, Vector
from mcbat.api.pitch import DEFAULT_EXTENSION, plate_speed
from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL, Ball, Bat
from mcbat.bodies.restitution import GAME_RESTITUTION, Restitution
from mcbat.bodies.swing import DEFAULT_PIVOT
from mcbat.checks import check_real as _real
from mcbat.core import status as st
from mcbat.errors import InputError
from mcbat.solving import solve_games
from mcbat.solving.derived import derive_game
from mcbat.solving.names import (
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    MAX_MU,
    MAX_SPEED,
    MAX_SPIN,
    OUTPUT_FIELDS,
    SWEET_SPOT_FROM_BARREL_END,
    bat_frame_columns,
    incoming_state,
)
from mcbat.study.game_keys import KEYS as GAME_KEYS
from mcbat.study.game_keys import check_swing_angles, parse_handedness
from mcbat.study.units import LENGTH, SPEED

__all__ = ["GAME_JSON_KEYS", "GameCase", "GameResult", "game_case_from_dict", "solve_game"]

GAME_JSON_KEYS = {  # Python parameter -> (JSON section, key)
    "pitch_speed": ("pitch", "speed"),
    "vertical_approach_angle": ("pitch", "vertical_approach_angle"),
    "horizontal_approach_angle": ("pitch", "horizontal_approach_angle"),
    "spin_rate": ("pitch", "spin_rate"), "spin_axis": ("pitch", "spin_axis"),
    "spin_efficiency": ("pitch", "spin_efficiency"), "gyro_sign": ("pitch", "gyro_sign"),
    "bat_speed": ("swing", "bat_speed"), "attack_angle": ("swing", "attack_angle"),
    "attack_direction": ("swing", "attack_direction"),
    "vertical_bat_angle": ("swing", "vertical_bat_angle"), "pivot": ("swing", "pivot"),
    "from_barrel_end": ("contact", "from_barrel_end"), "undercut": ("contact", "undercut"),
}
"""Where each parameter of ``GameCase`` sits in the JSON contract of ``mcbat impact``
(``pitch_speed`` is ``pitch.speed``): errors of a JSON case name the JSON key."""
_RIGHT_ANGLE = math.pi / 2


def _radians(value: float) -> str:
    """An angle received in radians, shown as given and in degrees (a value in degrees
    passed by mistake shows as such)."""
    return f"{value:.6g} rad ({math.degrees(value):.6g} deg; GameCase takes radians)"


def _solver_range(value: float, name: str, high: float, unit: str) -> None:
    """A game input beyond the solver's range (``docs/physics.md``, "Valid inputs"): the
    impact's velocities and spins scale with it."""
    if not value <= high:
        raise InputError(name, f"must be at most {high:g}{' ' + unit if unit else ''} (the "
                         f"range the solver works in, docs/physics.md), got {value:.6g}"
                         f"{' ' + unit if unit else ''}")


@dataclass(frozen=True)
class GameCase:
    """One game situation. **Plain numbers in SI units: m/s, rad, rad/s, m** -- not the
    mph, deg and rpm of Statcast and of a study's ``{value, unit}`` tables (convert with
    ``math.radians``, ``mph * M_S_PER_MPH``, ``rpm * RAD_S_PER_RPM`` from
    ``mcbat.core.units``; ``docs/batting.md``).

    ==================================  ======  ==============================================
    parameter                           unit    meaning
    ==================================  ======  ==============================================
    ``pitch_speed``, ``bat_speed``      m/s     the pitch; the sweet spot's speed
    ``vertical_approach_angle``         rad     < 0 descending; within (-pi/2, pi/2)
    ``horizontal_approach_angle``       rad     > 0 moving towards ``+x``; within (-pi/2, pi/2)
    ``spin_rate``                       rad/s   the pitch's spin
    ``spin_axis``                       rad     Statcast's: pi backspin, 0 topspin
    ``spin_efficiency``                 1       transverse fraction, in [0, 1]
    ``gyro_sign``                       1       +1 or -1: the sense of the gyro part
    ``attack_angle``                    rad     the swing's; within (-pi/2, pi/2)
    ``attack_direction``                rad     > 0 towards the opposite field
    ``vertical_bat_angle``              rad     within (-pi/2, pi/2)
    ``pivot``                           m       the pivot's distance from the knob
    ``from_barrel_end``, ``undercut``   m       the contact; undercut > 0: ball centre above
    ``mu``                              1       Coulomb friction, >= 0
    ==================================  ======  ==============================================

    The field frame: ``x`` to first base, ``y`` to the pitcher, ``z`` up. ``handedness``
    "R" or "L" (mirror image in ``x``). ``restitution`` gives ``e*`` and ``e_x``
    (``mcbat.bodies.restitution.Restitution``; default the game preset). A value out of its
    range raises ``mcbat.errors.InputError`` naming the parameter and the value
    received (an angle in degrees by mistake, ``attack_angle=10``, is refused: 10 rad lies
    beyond pi/2).
    """

    ball: Ball
    bat: Bat
    pitch_speed: float
    bat_speed: float
    mu: float
    handedness: str = "R"
    vertical_approach_angle: float = 0.0
    horizontal_approach_angle: float = 0.0
    spin_rate: float = 0.0
    spin_axis: float = math.pi
    spin_efficiency: float = 1.0
    gyro_sign: float = 1.0
    attack_angle: float = 0.0
    attack_direction: float = 0.0
    vertical_bat_angle: float = 0.0
    pivot: float = DEFAULT_PIVOT
    from_barrel_end: float = SWEET_SPOT_FROM_BARREL_END
    undercut: float = 0.0
    restitution: Restitution = GAME_RESTITUTION

    def __post_init__(self) -> None:  # noqa: C901 - one check per key, in the contract's order
        for name, kind in (("ball", Ball), ("bat", Bat), ("restitution", Restitution)):
            if not isinstance(getattr(self, name), kind):
                raise InputError(name, f"must be a {kind.__module__}.{kind.__name__}, got "
                                 f"{getattr(self, name)!r}")
        bat = self.bat
        if bat.length is None or bat.cm_from_barrel_end is None:
            raise InputError("bat", "a game needs the bat's length and CM (cm_from_knob), "
                             "or a bat preset")
        parse_handedness(self.handedness)
        object.__setattr__(self, "pitch_speed",
                           _real(self.pitch_speed, "pitch_speed", positive=True))
        for name in ("vertical_approach_angle", "horizontal_approach_angle"):
            value = _real(getattr(self, name), name)
            if not abs(value) < _RIGHT_ANGLE:
                raise InputError(name, f"must lie within (-90, 90) deg for a pitch moving "
                                 f"towards the plate, got {_radians(value)}")
        object.__setattr__(self, "spin_rate", _real(self.spin_rate, "spin_rate", minimum=0.0))
        _solver_range(self.pitch_speed, "pitch_speed", MAX_SPEED, "m/s")
        _solver_range(self.spin_rate, "spin_rate", MAX_SPIN, "rad/s")
        object.__setattr__(self, "spin_axis", _real(self.spin_axis, "spin_axis"))
        object.__setattr__(self, "spin_efficiency",
                           _real(self.spin_efficiency, "spin_efficiency", minimum=0.0, maximum=1.0))
        if self.gyro_sign not in (1, -1):
            raise InputError("gyro_sign", f"must be +1 or -1, got {self.gyro_sign!r}")
        object.__setattr__(self, "bat_speed", _real(self.bat_speed, "bat_speed", minimum=0.0))
        _solver_range(self.bat_speed, "bat_speed", MAX_SPEED, "m/s")
        for name in ("attack_angle", "attack_direction", "vertical_bat_angle"):
            value = _real(getattr(self, name), name)
            if not abs(value) < _RIGHT_ANGLE:
                raise InputError(name, f"must lie within (-90, 90) deg, got {_radians(value)}")
        check_swing_angles(self.attack_angle, self.vertical_bat_angle, "vertical_bat_angle")
        sweet = bat.length - SWEET_SPOT_FROM_BARREL_END
        object.__setattr__(self, "pivot", _real(self.pivot, "pivot", minimum=0.0))
        if not self.pivot < sweet:
            raise InputError("pivot", f"must lie between the knob and the sweet spot "
                             f"(< {sweet:.4g} m from the knob), got {self.pivot!r}")
        object.__setattr__(self, "from_barrel_end",
                           _real(self.from_barrel_end, "from_barrel_end", minimum=0.0,
                                 maximum=bat.length))
        object.__setattr__(self, "mu", _real(self.mu, "mu", minimum=0.0))
        _solver_range(self.mu, "mu", MAX_MU, "")
        radius, slope = self.contact_surface()
        reach = radius + self.ball.radius / math.sqrt(1.0 + slope * slope)
        if not abs(_real(self.undercut, "undercut")) <= reach:
            raise InputError("undercut", f"|undercut| must be <= {reach:.6g} m, the reach of "
                             f"barrel and ball there (the ball misses), got {self.undercut!r}")

    @property
    def axial(self) -> float:
        """The contact's axial position from the bat CM (m)."""
        # a game bat has its length and CM (``__post_init__`` checks the bat)
        return cast(float, self.bat.cm_from_barrel_end) - self.from_barrel_end

    def contact_surface(self) -> tuple[float, float]:
        """Bat radius and slope at the contact."""
        return self.bat.surface_at(float(self.bat.clip_axial(self.axial)))

    def kernel_inputs(self) -> np.ndarray:
        """The case as one column of ``mcbat.core.swing.GAME_INPUT_FIELDS``."""
        radius, slope = self.contact_surface()
        rest = self.restitution
        row = {name: getattr(self, name) for name in GAME_JSON_KEYS}
        row.update(
            ball_mass=self.ball.mass, ball_radius=self.ball.radius,
            ball_inertia_factor=self.ball.inertia_factor, bat_mass=self.bat.mass,
            bat_transverse_inertia=self.bat.transverse_inertia,
            bat_axial_inertia=self.bat.axial_inertia, bat_length=self.bat.length,
            bat_cm_from_knob=(cast(float, self.bat.length)
                              - cast(float, self.bat.cm_from_barrel_end)),
            bat_radius=radius, bat_slope=slope,
            handedness=parse_handedness(self.handedness), mu=self.mu, e_ref=rest.e_ref,
            e_slope=rest.e_slope, e_speed_ref=rest.e_speed_ref,
            e_location_factor=rest.location_factor(self.from_barrel_end), e_x=rest.e_x)
        row = {("pitch_" + k if k in _PITCH_COLUMNS else k): v for k, v in row.items()}
        return np.array([[float(row[name])] for name in GAME_INPUT_FIELDS])

    def mirrored(self) -> GameCase:
        """The mirror image in ``x``: the other handedness, and the pitch mirrored
        (horizontal approach angle and spin axis negated, gyro sense reversed)."""
        return dataclasses.replace(
            self, handedness="L" if self.handedness == "R" else "R",
            horizontal_approach_angle=-self.horizontal_approach_angle,
            spin_axis=2.0 * math.pi - self.spin_axis, gyro_sign=-self.gyro_sign)

    @classmethod
    def from_dict(cls, data: Any) -> GameCase:
        """Build a game case from the JSON contract of ``mcbat impact`` (``docs/batting.md``;
        there ``{value, unit}`` tables give other units): see
        ``game_case_from_dict``."""
        return game_case_from_dict(data)


#: The pitch keys of a game case besides a study's: its speed at release instead of
#: at the plate (section key -> (quantity, default, name)).
_RELEASE_KEYS = {"release_speed": (SPEED, 0.0, "release_speed"),
                 "extension": (LENGTH, DEFAULT_EXTENSION, "extension")}

_PITCH_COLUMNS = ("speed", "vertical_approach_angle", "horizontal_approach_angle",
                  "spin_rate", "spin_axis", "spin_efficiency", "gyro_sign")


@dataclass(frozen=True)
class GameResult:
    """A solved game case: the batted ball in the field's conventions, the field-frame
    velocities and spins, and the bat-frame impact (``impact``, an ``ImpactResult``
    whose ``case`` re-solves in the bat frame alone).

    **Mixed units, as Statcast gives them**: ``launch_speed`` in mph, ``launch_angle`` and
    ``spray_angle`` in deg, ``spin_rate``, ``backspin``, ``sidespin``, ``gyrospin`` in rpm
    (``batted_ball``); the field-frame vectors (``ball_velocity``, ``ball_spin``...)
    in m/s and rad/s. To fly the ball, ``mcbat.api.FlightCase.from_result`` converts
    them (a ``mcbat.api.FlightCase`` takes SI).
    """

    case: GameCase
    impact: ImpactResult
    collision_efficiency: float
    ball_velocity: Vector
    ball_spin: Vector
    bat_velocity: Vector
    bat_spin: Vector
    pitch_velocity: Vector
    pitch_spin: Vector
    bat_velocity_in: Vector
    bat_spin_in: Vector
    undercut_impact_parameter: float

    @property
    def batted_ball(self) -> dict[str, float]:
        """``launch_speed`` (mph), ``launch_angle``, ``spray_angle`` (deg), ``spin_rate``,
        ``backspin``, ``sidespin``, ``gyrospin`` (rpm)."""
        ball: dict[str, float] = derive_game(self.ball_velocity, self.ball_spin)
        return ball

    def __getattr__(self, name: str) -> float:
        if name in ("launch_speed", "launch_angle", "spray_angle", "spin_rate", "backspin",
                    "sidespin", "gyrospin"):
            return self.batted_ball[name]
        raise AttributeError(name)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (the output of ``mcbat impact`` for a game case), with a
        ``units`` block: see ``mcbat.api.contract.game_result_to_dict``. ``mcbat flight``
        reads it as it is (``docs/flight.md``)."""
        return game_result_to_dict(self)


# SolverSettings is frozen: one default instance shared by every call is safe.
def solve_game(case: GameCase,
               settings: SolverSettings = SolverSettings()) -> GameResult:  # noqa: B008
    """Solve one game situation with the game kernel (the one ``mcbat run`` uses).

    Raises
    ------
    InputError
        Naming ``pitch_speed`` if the ball does not approach the bat at the contact.
        Also if the kernel reports another failure status, naming it.
    """
    g = case.kernel_inputs()
    frame, out, game_out, status, end_state = solve_games(g, settings)
    code = int(status[0])
    if code == st.NOT_APPROACHING:
        raise InputError("pitch_speed", "the ball does not approach the bat at the contact "
                         "(a pitch moving away from the swing)")
    if code != st.OK:
        raise InputError(None, f"the solver cannot solve this impact (status "
                         f"{st.STATUS_NAMES[code]!r}: docs/errors.md lists what each status "
                         "means)")
    b = {name: column[0] for name, column in bat_frame_columns(g, frame).items()}
    o = dict(zip(OUTPUT_FIELDS, out[:, 0]))
    go = dict(zip(GAME_OUTPUT_FIELDS, game_out[:, 0]))

    def vec(d: dict[str, Any], fmt: str) -> Vector:
        x, y, z = (float(d[fmt.format(c)]) for c in "xyz")
        return x, y, z

    pitch_v, pitch_w, bat_v, bat_w = ((float(v[0]), float(v[1]), float(v[2]))
                                      for v in incoming_state(g, 0))

    impact_case = ImpactCase(
        ball=case.ball, bat=case.bat, contact=Contact(axial=float(b["axial"]),
                                                      angle=float(b["angle"])),
        ball_velocity=vec(b, "ball_v{}_in"), ball_spin=vec(b, "ball_w{}_in"),
        bat_velocity=vec(b, "bat_v{}_in"), bat_spin=vec(b, "bat_w{}_in"),
        mu=float(b["mu"]), e=float(b["e"]), e_x=float(b["e_x"]))
    stick = float(o["stick_impulse"])
    crit = float(o["stick_criterion"])
    impact = ImpactResult(
        case=impact_case, status="ok", end_state=st.END_STATE_NAMES[int(end_state[0])],
        ball_velocity=vec(o, "ball_v{}"), ball_spin=vec(o, "ball_w{}"),
        bat_velocity=vec(o, "bat_v{}"), bat_spin=vec(o, "bat_w{}"),
        normal_impulse=float(o["normal_impulse"]),
        stick_impulse=None if math.isnan(stick) else stick,
        compression_impulse=float(o["compression_impulse"]),
        tangential_impulse=(float(o["tangential_impulse_1"]), float(o["tangential_impulse_2"])),
        compression_work=float(o["compression_work"]), normal_work=float(o["normal_work"]),
        friction_work=float(o["friction_work"]),
        stick_criterion=None if math.isnan(crit) else crit,
        energy_in=float(o["energy_in"]), energy_out=float(o["energy_out"]),
        rk4_steps=int(o["rk4_steps"]))
    return GameResult(
        case=case, impact=impact, collision_efficiency=float(go["collision_efficiency"]),
        ball_velocity=vec(go, "field_ball_v{}"), ball_spin=vec(go, "field_ball_w{}"),
        bat_velocity=vec(go, "field_bat_v{}"), bat_spin=vec(go, "field_bat_w{}"),
        pitch_velocity=pitch_v, pitch_spin=pitch_w, bat_velocity_in=bat_v, bat_spin_in=bat_w,
        undercut_impact_parameter=float(go["impact_parameter"]))


def game_case_from_dict(data: Any) -> GameCase:
    """A game case of ``mcbat impact`` (``docs/batting.md``): numbers as
    ``{"value": ..., "unit": ...}``, or bare numbers in the field's units where the field
    measures the key (``pitch.speed`` mph, angles deg, ``pitch.spin_rate`` rpm:
    ``mcbat.api.contract.FIELD_KEYS``) and in SI elsewhere (the bat, the contact,
    ``swing.pivot``, the restitution); errors name the JSON keys (``pitch.speed``).

    The pitch's speed is ``pitch.speed``, at the front of the plate, or
    ``pitch.release_speed`` (with ``pitch.extension``, default 6.3 ft), at release, as
    Statcast gives it: converted to the plate by the pitch's flight
    (``mcbat.api.pitch.plate_speed``).
    """
    allowed = {"handedness", "ball", "bat", "pitch", "swing", "contact", "mu", "restitution"}
    check_object(data, "", allowed, ("bat", "pitch", "swing", "mu"))
    ball = (BALL_PRESETS[DEFAULT_BALL] if "ball" not in data
            else located("ball", ball_from_dict, data["ball"]))
    bat = located("bat", bat_from_dict, data["bat"], game=True)
    values: dict[str, Any] = {}
    for section in ("pitch", "swing", "contact"):
        keys: dict[str, Any] = dict(cast("dict[str, Any]", GAME_KEYS[section]))
        if section == "pitch":
            keys.update(_RELEASE_KEYS)
        table = check_object(data.get(section, {}), section, set(keys),
                             [k for k, spec in keys.items()
                              if spec[1] is None and k != "speed"])
        for key, spec in table.items():
            values[keys[key][2].removeprefix("pitch_") if section == "pitch" else
                   keys[key][2]] = field_value(spec, f"{section}.{key}", keys[key][0])
    pitch = data["pitch"]
    if ("speed" in pitch) == ("release_speed" in pitch):
        raise InputError("pitch.speed", "give exactly one of pitch.speed (at the front of "
                         "the plate) and pitch.release_speed (at release, Statcast's "
                         "release_speed)")
    if "extension" in pitch and "release_speed" not in pitch:
        raise InputError("pitch.extension", "only with pitch.release_speed (the release "
                         "point's distance in front of the rubber)")
    if "release_speed" in pitch:
        release = values.pop("release_speed")
        extension = values.pop("extension", DEFAULT_EXTENSION)
        spin = {k: values[k] for k in ("spin_rate", "spin_axis", "spin_efficiency",
                                       "gyro_sign") if k in values}
        values["speed"] = located("pitch", plate_speed, release, extension, ball=ball,
                                  **spin)
    values["pitch_speed"] = values.pop("speed")
    mu = fixed_value(data["mu"], "mu", "dimensionless")
    restitution = GAME_RESTITUTION
    if "restitution" in data:
        keys = cast("dict[str, Any]", GAME_KEYS["restitution"])
        rest = check_object(data["restitution"], "restitution", set(keys) | {"location"}, ())
        if ("e" in rest) == ("e_ref" in rest):
            raise InputError("restitution", "give exactly one of 'e' (a constant e*) or "
                             "'e_ref' (with e_slope and e_speed_ref)")
        kw: dict[str, Any] = {
            ("e_ref" if k == "e" else k): (fixed_value(v, f"restitution.{k}", keys[k][0])
                                           if k != "location" else v)
            for k, v in rest.items()}
        restitution = located("restitution", Restitution, **kw)
    handedness = data.get("handedness", "R")
    try:
        return GameCase(ball=ball, bat=bat, mu=mu, handedness=handedness,
                        restitution=restitution, **values)
    except InputError as err:
        if err.field == "pitch_speed" and "release_speed" in pitch:
            raise InputError("pitch.release_speed", f"{err.message} (the speed at the "
                             "plate, from this release speed)") from None
        if err.field in GAME_JSON_KEYS:
            section, key = GAME_JSON_KEYS[err.field]
            raise InputError(f"{section}.{key}", err.message) from None
        raise
