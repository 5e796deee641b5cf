"""One batted ball's flight to the landing point (``docs/flight.md``).

``FlightCase``, the Python class, takes plain numbers in SI units (m/s, rad, rad/s).
A game's batted ball, ``mcbat.api.GameResult``, is in Statcast's units (mph, deg,
rpm): fly it with ``FlightCase.from_result``, which converts them. The JSON of
``mcbat flight`` (``flight_case_from_dict``) reads a bare number in the field's unit
(mph, deg, rpm, ft: ``mcbat.api.contract.FIELD_KEYS``), as the answers give them.

Example
-------
>>> import math
>>> from mcbat.api import FlightCase, solve_flight
>>> from mcbat.core.units import M_S_PER_MPH
>>> case = FlightCase(launch_speed=103 * M_S_PER_MPH, launch_angle=math.radians(27),
...                   backspin=2000 * 2 * math.pi / 60)
>>> result = solve_flight(case)
>>> 400 < result.hit_distance < 450           # ft
True
>>> result.to_dict()["units"]["hit_distance"]
'ft'
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, cast

import numpy as np

from mcbat.api.contract import (
    FIELD_KEYS,
    FT,
    check_object,
    field_spec,
    field_value,
    fixed_value,
    flight_result_to_dict,
    located,
)
from mcbat.api.game import GameResult
from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL, Ball
from mcbat.checks import check_real as _real
from mcbat.errors import InputError
from mcbat.solving import FlightStatus, fly_one, fly_sampled
from mcbat.solving.derived import launch_vectors
from mcbat.study import units as u
from mcbat.study.flight import FLIGHT_KEYS, FlightSettings, parse_flight
from mcbat.study.spec import parse_ball

__all__ = ["MAX_TRAJECTORY_POINTS", "FlightCase", "FlightResult", "flight_case_from_dict",
           "solve_flight"]

#: The launch numbers of a flight, as a ``mcbat.api.GameResult`` reports them (in
#: the field's units, ``mcbat.api.contract.FIELD_KEYS``).
_LAUNCH_NAMES = ("launch_speed", "launch_angle", "spray_angle", "backspin", "sidespin",
                 "gyrospin")


def _angle(value: float, name: str, limit: float, shown: int) -> float:
    value = _real(value, name)
    if not abs(value) <= limit:
        raise InputError(name, f"must be within [-{shown}, {shown}] deg, got {value:.6g} rad "
                         f"({math.degrees(value):.6g} deg; FlightCase takes radians)")
    return value


@dataclasses.dataclass(frozen=True)
class FlightCase:
    """One batted ball to fly. **Plain numbers in SI units: m/s, rad, rad/s** -- not the
    mph, deg and rpm of Statcast and of ``mcbat.api.GameResult`` (for a game's ball
    use ``from_result``, which converts them).

    ========================================  ======  =====================================
    parameter                                 unit    meaning
    ========================================  ======  =====================================
    ``launch_speed``                          m/s     > 0
    ``launch_angle``                          rad     the velocity's elevation, within
                                                      [-pi/2, pi/2]
    ``spray_angle``                           rad     ``atan2(v_x, v_y)``, > 0 towards
                                                      right field, within [-pi, pi]
    ``backspin``, ``sidespin``, ``gyrospin``  rad/s   the spin along ``b = unit(v x z)``,
                                                      ``s = b x unit(v)`` and ``unit(v)``
    ========================================  ======  =====================================

    ``ball`` (default the ``baseball`` preset) and ``settings``
    (``mcbat.study.flight.FlightSettings``: atmosphere, model, launch point, wind,
    scheme). A value out of its range raises ``mcbat.errors.InputError`` naming
    the parameter and the value received (an angle in degrees by mistake,
    ``launch_angle=27``, is refused: 27 rad lies beyond pi/2).
    """

    launch_speed: float
    launch_angle: float
    spray_angle: float = 0.0
    backspin: float = 0.0
    sidespin: float = 0.0
    gyrospin: float = 0.0
    ball: Ball = BALL_PRESETS[DEFAULT_BALL]
    settings: FlightSettings = FlightSettings()

    def __post_init__(self) -> None:
        speed = _real(self.launch_speed, "launch_speed")
        if not speed > 0.0:
            raise InputError("launch_speed", f"must be > 0 m/s, got {speed:.6g} m/s")
        object.__setattr__(self, "launch_speed", speed)
        object.__setattr__(self, "launch_angle",
                           _angle(self.launch_angle, "launch_angle", math.pi / 2, 90))
        object.__setattr__(self, "spray_angle",
                           _angle(self.spray_angle, "spray_angle", math.pi, 180))
        for name in ("backspin", "sidespin", "gyrospin"):
            object.__setattr__(self, name, _real(getattr(self, name), name))
        if not isinstance(self.ball, Ball):
            raise InputError("ball", f"must be a mcbat.bodies.Ball, got "
                             f"{type(self.ball).__name__}")
        if not isinstance(self.settings, FlightSettings):
            raise InputError("settings", f"must be a mcbat.study.flight.FlightSettings, got "
                             f"{type(self.settings).__name__}")

    @classmethod
    def from_result(cls, result: GameResult, settings: FlightSettings | None = None, *,
                    ball: Ball | None = None) -> FlightCase:
        """The flight of a game's batted ball: its launch numbers, given in Statcast's
        units (mph, deg, rpm), converted to SI; its ball, the game's ball.

        Parameters
        ----------
        result : GameResult
            A solved game (``mcbat.api.solve_game``, ``mcbat.solve``).
        settings : FlightSettings, optional
            Atmosphere, model, launch point... (default: the calculator's standard
            conditions).
        ball : Ball, optional
            Another ball to fly (default: the game's).

        Examples
        --------
        >>> import math, mcbat
        >>> from mcbat.api import FlightCase, GameCase
        >>> from mcbat.bodies import BALL_PRESETS, bat_preset
        >>> game = mcbat.solve(GameCase(ball=BALL_PRESETS["baseball"], bat=bat_preset("r161"),
        ...                             pitch_speed=40.0, bat_speed=31.0, mu=0.5,
        ...                             attack_angle=math.radians(10.0)))
        >>> case = FlightCase.from_result(game)
        >>> from mcbat.core.units import M_S_PER_MPH
        >>> round(case.launch_speed / M_S_PER_MPH, 9) == round(game.launch_speed, 9)
        True
        """
        if not isinstance(result, GameResult):
            raise InputError("result", "must be a GameResult (a solved game case: its batted "
                             f"ball is in the field frame), got {type(result).__name__}")
        launch = {name: u.to_si(result.batted_ball[name], FIELD_KEYS[name][0],
                                FIELD_KEYS[name][1], name) for name in _LAUNCH_NAMES}
        return cls(**launch, ball=result.case.ball if ball is None else ball,
                   settings=FlightSettings() if settings is None else settings)

    def vectors(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """Field-frame velocity (m/s) and spin (rad/s) at launch."""
        v, w = launch_vectors(self.launch_speed, self.launch_angle, self.spray_angle,
                              self.backspin, self.sidespin, self.gyrospin)
        return tuple(float(x) for x in v), tuple(float(x) for x in w)


@dataclasses.dataclass(frozen=True)
class FlightResult:
    """Where and when the ball lands (``hit_distance``, ``landing_x``, ``landing_y``,
    ``apex`` in ft as Statcast gives them; ``*_m`` in m; ``hang_time`` in s), and the
    sampled trajectory if asked for (t in s, x, y, z in m)."""

    hit_distance_m: float
    landing_x_m: float
    landing_y_m: float
    hang_time: float
    apex_m: float
    steps: int
    trajectory: dict[str, list[float]] | None = None

    @property
    def hit_distance(self) -> float:
        """Horizontal distance of the landing point from home plate (ft)."""
        return self.hit_distance_m / FT

    @property
    def landing_x(self) -> float:
        """Landing point towards first base (ft)."""
        return self.landing_x_m / FT

    @property
    def landing_y(self) -> float:
        """Landing point towards centre field (ft)."""
        return self.landing_y_m / FT

    @property
    def apex(self) -> float:
        """Greatest height of the flight (ft)."""
        return self.apex_m / FT

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (the output of ``mcbat flight``), with a ``units`` block:
        see ``mcbat.api.contract.flight_result_to_dict``."""
        return flight_result_to_dict(self)

_LAUNCH_KEYS = {"launch_speed": (u.SPEED, None), "launch_angle": (u.ANGLE, None),
                "spray_angle": (u.ANGLE, 0.0), "backspin": (u.SPIN, 0.0),
                "sidespin": (u.SPIN, 0.0), "gyrospin": (u.SPIN, 0.0)}
#: The keys of a game's answer that a flight does not read (its ball comes from
#: ``bat_frame_case.ball``).
_GAME_ANSWER_KEYS = {"status", "end_state", "spin_rate", "collision_efficiency", "field",
                     "bat_frame_case", "bat_frame"}


def _launch_units(data: dict[str, Any], game_answer: bool) -> dict[str, str]:
    """The ``units`` block of a flight's input: the unit of each bare launch number (a key
    it does not name: the field's unit)."""
    if "units" not in data:
        return {}
    units = data["units"]
    if not isinstance(units, dict):
        raise InputError("units", f"must be an object, got {type(units).__name__}")
    out: dict[str, str] = {}
    for key, unit in units.items():
        if key in _LAUNCH_KEYS:
            if not isinstance(unit, str):
                raise InputError(f"units.{key}", f"must be a unit's name, got {unit!r}")
            u.factor(unit, _LAUNCH_KEYS[key][0], f"units.{key}")  # validates the unit
            out[key] = unit
        elif not (game_answer and key in _GAME_ANSWER_KEYS):
            raise InputError(f"units.{key}", "a units block names the units of the launch "
                             f"numbers only ({', '.join(_LAUNCH_KEYS)}); write other values "
                             "as {value, unit}")
    return out


def flight_case_from_dict(data: Any) -> FlightCase:
    """A ``FlightCase`` from a ``mcbat flight`` JSON object: bare numbers in the
    field's units (``launch_speed`` mph, angles deg, spins rpm, ``position`` and
    ``landing_height`` ft, ``wind`` mph, ``atmosphere`` degF, inHg, ft:
    ``mcbat.api.contract.FIELD_KEYS``; the other keys SI), or in the units a ``units``
    block names for the launch numbers (``{"launch_speed": "m/s", ...}``), or values as
    ``{"value": ..., "unit": ...}``.

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
    check_object(data, "", allowed | (_GAME_ANSWER_KEYS if game_answer else set()),
                 ("launch_speed", "launch_angle"))
    if game_answer and data.get("status", "ok") != "ok":
        raise InputError("status", f"the game was not solved (status {data['status']!r})")
    units = _launch_units(data, game_answer)

    def shown(key: str) -> str:  # the value as written, with the unit it is read in
        value = data[key]
        if isinstance(value, dict):
            return repr(value)
        return f"{value!r} {units.get(key, FIELD_KEYS[key][0])}"

    launch: dict[str, float] = {}
    for key, (quantity, default) in _LAUNCH_KEYS.items():
        spec = data.get(key, default)
        if key not in data:
            value = cast(float, default)  # (the keys without a default are required)
        elif key in units and not isinstance(spec, dict):
            value = fixed_value({"value": spec, "unit": units[key]}, key, quantity)
        else:
            value = field_value(spec, key, quantity)
        if not math.isfinite(value):
            raise InputError(key, f"must be a finite number, got {shown(key)}")
        launch[key] = value
    if not launch["launch_speed"] > 0.0:
        raise InputError("launch_speed", f"must be > 0, got {shown('launch_speed')}")
    if not abs(launch["launch_angle"]) <= math.pi / 2:
        raise InputError("launch_angle", f"must be within [-90, 90] deg, got "
                         f"{shown('launch_angle')}")
    if "ball" in data:
        ball = parse_ball(data["ball"])
    elif game_answer:
        case = data.get("bat_frame_case")
        if not isinstance(case, dict) or "ball" not in case:
            raise InputError("bat_frame_case.ball", "missing: a game's answer names its ball "
                             "there (or give 'ball')")
        ball = located("bat_frame_case", parse_ball, case["ball"])
    else:
        ball = BALL_PRESETS[DEFAULT_BALL]
    settings = parse_flight(_settings_in_field_units(data), field="")
    return FlightCase(ball=ball, settings=settings, **launch)


def _settings_in_field_units(data: dict[str, Any]) -> dict[str, Any]:
    """The flight keys of a case, their bare numbers given the field's units
    (``mcbat.api.contract.field_spec``), for ``mcbat.study.flight.parse_flight``
    (which reads bare numbers in SI, as a study's ``[flight]`` section)."""
    out = {k: field_spec(v, k) for k, v in data.items() if k in FLIGHT_KEYS}
    if isinstance(out.get("atmosphere"), dict):
        out["atmosphere"] = {k: field_spec(v, f"atmosphere.{k}")
                             for k, v in out["atmosphere"].items()}
    return out


#: Most points of a sampled trajectory (``mcbat flight --trajectory DT``); a flight is also
#: sampled over at most its first 120 s.
MAX_TRAJECTORY_POINTS = 100_000


def solve_flight(case: FlightCase, trajectory: float | None = None) -> FlightResult:
    """Fly one ball with the flight kernel (the one studies use).

    ``trajectory`` (a time step, s, > 0): also sample the flight every that many seconds (and at the
    landing).

    Raises
    ------
    InputError
        Naming ``trajectory``, ``position`` for a launch that cannot fly, or
        ``landing_height`` for a ball that never rises to it.
    """
    v, w = case.vectors()
    params = case.settings.params(case.ball.mass, case.ball.radius)
    x = tuple(float(c) for c in case.settings.start)
    sampled: dict[str, list[float]] | None = None
    if trajectory is None:
        f, count, samples = fly_one(params, x, v, w), 0, None
    else:
        dt = _real(trajectory, "trajectory")
        if not dt > 0.0:
            raise InputError("trajectory", f"must be > 0 s, got {trajectory!r}")
        if case.settings.scheme == "sheet":
            raise InputError("trajectory", "not available with scheme = \"sheet\"")
        samples = np.empty((4, int(min(120.0 / dt, MAX_TRAJECTORY_POINTS)) + 2))
        f, count = fly_sampled(params, x, v, w, samples, dt)
    if f.status == FlightStatus.NOT_RISEN:
        raise InputError("landing_height", "the ball never rises to the landing height: it "
                         "reaches the ground first")
    if f.status == FlightStatus.INVALID:  # the launch point: below the ground, or not finite
        raise InputError("position", "the ball cannot fly from there (below the ground)")
    landing = (f.distance, f.landing_x, f.landing_y, f.hang_time, f.apex)
    if f.status != FlightStatus.OK or not all(math.isfinite(value) for value in landing):
        # A successful answer holds numbers only: a ball the model cannot carry (a
        # feather's mass, a balloon's radius, a launch near the speed of light) is the
        # input's fault, said so, not a null in the output. A ball that hovers (a 36 km
        # radius: drag far above its weight) runs out of steps before it lands: the same.
        raise InputError("launch_speed", f"the flight model has no finite landing for a "
                         f"{case.ball.mass:.3g} kg ball of radius {case.ball.radius:.3g} m "
                         f"launched at {case.launch_speed:.3g} m/s (ball.mass, ball.radius, "
                         "launch_speed): outside the range the model is made for")
    trajectory = None
    if samples is not None:
        if count and samples[0, count - 1] + dt < f.hang_time and count >= samples.shape[1]:
            needed = f.hang_time / dt
            raise InputError("trajectory", f"a {f.hang_time:.3g} s flight sampled every "
                             f"{dt:g} s needs {needed:,.0f} points, at most "
                             f"{MAX_TRAJECTORY_POINTS:,} (and 120 s of flight): choose a "
                             f"step of at least {f.hang_time / MAX_TRAJECTORY_POINTS:.2g} s")
        t, px, py, pz = (samples[i, :count].tolist() for i in range(4))
        if not t or t[-1] < f.hang_time:
            t, px, py, pz = (t + [f.hang_time], px + [f.landing_x], py + [f.landing_y],
                             pz + [0.0])
        sampled = {"t": t, "x": px, "y": py, "z": pz}
    return FlightResult(hit_distance_m=float(f.distance), landing_x_m=float(f.landing_x),
                        landing_y_m=float(f.landing_y), hang_time=float(f.hang_time),
                        apex_m=float(f.apex), steps=int(f.steps), trajectory=sampled)
