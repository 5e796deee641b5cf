"""Flight settings: the atmosphere, the aerodynamic model and the integrator, as written in
a study's ``[flight]`` section or a ``mcbat flight`` case (the same keys, units and checks).

Keys (all optional)::

    model = "nathan"            # or "sawicki2003", "constant" (then drag = C_D, lift = C_L)
    preset = "NAME"             # instead of model and scales: a calibrated flight
                                # (FLIGHT_PRESETS)
    drag_scale = 1              # nathan, sawicki2003: C_D0 = 0.3008 drag_scale
    lift_scale = 1              # nathan, sawicki2003: C_L times lift_scale
    landing_height = 0          # m (or {value, unit}): where the descending ball stops
    spin_decay_time = 30        # s; the model's default when absent; "none" (or JSON null)
    position = [0, 2, 3]        # launch point (field frame, m or {value, unit}); (0, 2, 3) ft
    wind = [0, 0, 0]            # m/s (field frame), or {value = [...], unit = "mph"}
    scheme = "adaptive"         # or "sheet": the spreadsheet's Euler steps of 0.01 s
    tolerance = 1e-6            # the adaptive integrator's local error tolerance (default 1e-5)
    [atmosphere]
    temperature = { value = 70, unit = "degF" }   # default 70 degF
    pressure = { value = 29.92, unit = "inHg" }   # barometric, corrected to sea level
    relative_humidity = 50                        # percent
    elevation = 0                                 # m (or ft) above sea level

Defaults are the calculator's standard conditions (70 degF, 29.92 inHg, 50 %, sea level).
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass
from importlib import resources

import numpy as np

from mcbat.checks import check_keys, number
from mcbat.errors import InputError
from mcbat.solving import fly_balls_each
from mcbat.solving import heights_at_distance as heights_at_distance_each
from mcbat.solving.derived import launch_vectors
from mcbat.solving.names import (
    FLIGHT_FIELDS,
    GRAVITY,
    MODELS,
    Aero,
    FlightParams,
    air_density,
    pack_params,
)
from mcbat.solving.settings import FLIGHT_TOLERANCE_RANGE, SolverSettings
from mcbat.study import units as u
from mcbat.study.distributions import parse

__all__ = ["DEFAULT_DECAY_TIME", "DEFAULT_START", "FLIGHT_KEYS", "FLIGHT_PRESETS", "SCALE_RANGES",
           "SEASONS_FILE", "flight_seasons", "season_scales", "season_wind_scale",
           "PER_BALL", "FlightSettings", "fly_launches", "heights_at_distance", "launch_vectors",
           "params_each", "parse_flight"]

#: The spin decay time of each model when none is given (s; None: no decay).
DEFAULT_DECAY_TIME = {"nathan": 30.0, "sawicki2003": None, "constant": None}
#: The calculator's launch point: 2 ft in front of the plate, 3 ft up (m).
DEFAULT_START = (0.0, 0.6096, 0.9144)
#: 100 mph in m/s: the calculator's decay uses t |v| / (tau 100 mph).
_DECAY_SPEED = 44.704

_ATMOSPHERE = {  # key -> (quantity, default SI, (low, high) SI)
    "temperature": (u.TEMPERATURE, (70.0 - 32.0) * 5.0 / 9.0 + 273.15, (200.0, 350.0)),
    "pressure": (u.PRESSURE, 29.92 * 3386.389, (50_000.0, 120_000.0)),
    "relative_humidity": (u.DIMENSIONLESS, 50.0, (0.0, 100.0)),
    "elevation": (u.LENGTH, 0.0, (-500.0, 5000.0)),
}


@dataclass(frozen=True)
class FlightSettings:
    """Validated flight settings (SI: K, Pa, percent, m, s, m/s). The integrator's
    accuracy is ``solver`` (a ``mcbat.solving.SolverSettings``: its ``flight_tolerance``),
    the one type that carries every kernel's accuracy."""

    temperature: float = _ATMOSPHERE["temperature"][1]
    pressure: float = _ATMOSPHERE["pressure"][1]
    relative_humidity: float = 50.0
    elevation: float = 0.0
    model: str = "nathan"
    spin_decay_time: float | None = 30.0
    drag: float = 0.0
    lift: float = 0.0
    drag_scale: float = 1.0
    lift_scale: float = 1.0
    landing_height: float = 0.0
    preset: str | None = None
    start: tuple = DEFAULT_START
    wind: tuple = (0.0, 0.0, 0.0)
    scheme: str = "adaptive"
    solver: SolverSettings = SolverSettings()

    @property
    def tolerance(self) -> float:
        """The adaptive integrator's local error tolerance (``solver.flight_tolerance``;
        the key ``tolerance`` of a flight section)."""
        return self.solver.flight_tolerance

    @property
    def density(self) -> float:
        """Air density (kg/m^3), Nathan's formula."""
        return float(air_density(self.temperature - 273.15, self.pressure,
                                 self.relative_humidity, self.elevation))

    def params(self, mass: float, radius: float) -> FlightParams:
        """The kernel's ``mcbat.core.flight.FlightParams`` for a ball of ``mass``
        (kg) and ``radius`` (m)."""
        decay = 0.0 if self.spin_decay_time is None else 1.0 / (self.spin_decay_time
                                                                 * _DECAY_SPEED)
        return FlightParams(
            drag_factor=self.density * math.pi * radius * radius / (2.0 * mass),
            radius=radius, aero=Aero(MODELS[self.model], self.drag, self.lift,
                                     self.drag_scale, self.lift_scale),
            decay_rate=decay, gravity=GRAVITY, wind_x=self.wind[0], wind_y=self.wind[1],
            wind_z=self.wind[2],
            tolerance=0.0 if self.scheme == "sheet" else self.tolerance,
            landing_height=self.landing_height)

    def config(self) -> dict:
        """JSON-ready settings (SI), for metadata and summaries."""
        return {"temperature_K": self.temperature, "pressure_Pa": self.pressure,
                "relative_humidity_percent": self.relative_humidity,
                "elevation_m": self.elevation, "air_density_kg_m3": self.density,
                "model": self.model, "spin_decay_time_s": self.spin_decay_time,
                "drag": self.drag if self.model == "constant" else None,
                "lift": self.lift if self.model == "constant" else None,
                "preset": self.preset,
                "drag_scale": self.drag_scale, "lift_scale": self.lift_scale,
                "landing_height_m": self.landing_height,
                "start_m": list(self.start), "wind_m_s": list(self.wind),
                "scheme": self.scheme, "tolerance": self.tolerance}


def _fixed(spec, field, quantity, low=None, high=None):
    value = parse(spec, field, quantity, kinds=("fixed",)).value
    if not math.isfinite(value):
        raise InputError(field, f"must be a finite number, got {spec!r}")
    if low is not None and not low <= value <= high:
        raise InputError(field, f"must be within [{low:g}, {high:g}] "
                                f"({u.SI_UNITS[quantity]}), got {spec!r}")
    return value


def _vector(spec, field, quantity):
    unit = None
    if isinstance(spec, dict):
        check_keys(spec, field, ("value",), ("unit",))
        spec, unit = spec["value"], spec.get("unit")
    if not (isinstance(spec, list | tuple) and len(spec) == 3):
        raise InputError(field, f"must be a list of 3 numbers, got {spec!r}")
    values = []
    for i, x in enumerate(spec):
        x = number(x, f"{field}[{i}]")  # finite, not a boolean
        values.append(float(u.to_si(x, unit, quantity, field)))
    return tuple(values)


def _choice(spec, field, options):
    if not isinstance(spec, str) or spec not in options:
        raise InputError(field, f"must be one of: {', '.join(options)}; got {spec!r}")
    return spec


#: The keys of a flight section (and of the settings part of a ``mcbat flight`` case).
FLIGHT_KEYS = ("atmosphere", "model", "preset", "spin_decay_time", "drag", "lift",
               "drag_scale", "lift_scale", "landing_height", "position", "wind", "scheme",
               "tolerance")
#: Allowed ranges of the calibration scales.
SCALE_RANGES = {"drag_scale": (0.2, 3.0), "lift_scale": (0.0, 3.0)}
#: The season table inside the resource package ``mcbat.data``: Nathan's model with its
#: drag and lift fitted to each season's measured Statcast distances, each ball in its own
#: park and air (``docs/flight.md``; ``python -m validation flight_seasons`` writes it).
SEASONS_FILE = "flight_seasons.csv"


@functools.cache
def flight_seasons() -> dict:
    """The fitted flight of each season, ``{season: {...}}`` (cached): ``drag_scale`` and
    ``lift_scale`` as ``{"value", "error"}`` (68 %), ``sigma_ft`` (the per-ball scatter),
    ``balls`` fitted, ``judged`` (balls judged out of sample), ``wind_scale`` (the share
    of a weather table's recorded wind the balls were flown with), ``spin_model``, ``ball``
    and ``data`` (the files it was fitted to)."""
    text = resources.files("mcbat.data").joinpath(SEASONS_FILE).read_text(encoding="utf-8")
    rows = csv.DictReader(line for line in text.splitlines()
                          if line.strip() and not line.startswith("#"))
    out = {}
    for row in rows:
        out[int(row["season"])] = {
            "model": "nathan",
            **{k: {"value": float(row[k]), "error": float(row[k + "_error"])}
               for k in SCALE_RANGES},
            "sigma_ft": float(row["sigma_ft"]), "balls": int(row["balls"]),
            "judged": int(row["judged"]), "wind_scale": float(row["wind_scale"]),
            "spin_model": row["spin_model"],
            "ball": row["ball"], "data": row["data"],
        }
    return out


def season_scales(game_year):
    """``(drag_scale, lift_scale, fitted)`` of each row's season (arrays): the fitted
    season's scales, or the published model's 1 and 1 (``fitted`` False) for a season the
    table does not have."""
    years = np.asarray(game_year, float)
    drag, lift = np.ones(years.shape), np.ones(years.shape)
    fitted = np.zeros(years.shape, bool)
    for season, row in flight_seasons().items():
        rows = years == season
        drag[rows] = row["drag_scale"]["value"]
        lift[rows] = row["lift_scale"]["value"]
        fitted[rows] = True
    return drag, lift, fitted


def season_wind_scale() -> float:
    """The share of a weather table's recorded wind the fitted seasons' balls feel (the
    season table's ``wind_scale``; 1 when the table is empty)."""
    scales = {row["wind_scale"] for row in flight_seasons().values()}
    return scales.pop() if len(scales) == 1 else 1.0


#: Calibrated flights (``preset = NAME``): ``statcast_SEASON``, the fitted flight of each
#: season of ``flight_seasons``.
FLIGHT_PRESETS = {f"statcast_{season}": row for season, row in flight_seasons().items()}


def _aerodynamics(table, key) -> dict:
    """The model's keys of a flight section: ``model``, ``drag``, ``lift``, the scales, or
    a ``preset`` that sets them."""
    if "preset" in table:
        name = _choice(table["preset"], key("preset"), tuple(FLIGHT_PRESETS))
        for other in ("model", "drag", "lift", *SCALE_RANGES):
            if other in table:
                raise InputError(key(other), f"not with preset = {name!r} (the preset sets "
                                             f"the model and its scales)")
        preset = FLIGHT_PRESETS[name]
        return {"model": preset["model"], "preset": name,
                **{k: preset[k]["value"] for k in SCALE_RANGES}}
    out = {}
    model = _choice(table.get("model", "nathan"), key("model"), tuple(MODELS))
    out["model"] = model
    for name in ("drag", "lift"):
        if model == "constant":
            if name not in table:
                raise InputError(key(name), "required with model = \"constant\"")
            out[name] = _fixed(table[name], key(name), u.DIMENSIONLESS, 0.0, 2.0)
        elif name in table:
            raise InputError(key(name), "only with model = \"constant\"")
    for name, (low, high) in SCALE_RANGES.items():
        if name in table:
            if model == "constant":
                raise InputError(key(name), "not with model = \"constant\" (give drag and "
                                            "lift)")
            out[name] = _fixed(table[name], key(name), u.DIMENSIONLESS, low, high)
    return out


def parse_flight(table, field="flight") -> FlightSettings:
    """Validate a flight section (a dict, as TOML or JSON gives it).

    Raises
    ------
    InputError
        Naming the dotted key (``flight.atmosphere.relative_humidity``, ...).
    """
    check_keys(table, field, (), FLIGHT_KEYS)

    def key(*parts):
        return ".".join(p for p in (field, *parts) if p)

    out = {}
    atmosphere = table.get("atmosphere", {})
    check_keys(atmosphere, key("atmosphere"), (), tuple(_ATMOSPHERE))
    for name, (quantity, _, (low, high)) in _ATMOSPHERE.items():
        if name in atmosphere:
            out[name] = _fixed(atmosphere[name], key("atmosphere", name), quantity, low,
                               high)
    out.update(_aerodynamics(table, key))
    model = out["model"]
    if "landing_height" in table:
        out["landing_height"] = _fixed(table["landing_height"], key("landing_height"),
                                       u.LENGTH, 0.0, 10.0)
    decay = table.get("spin_decay_time", DEFAULT_DECAY_TIME[model])
    if decay is None or decay == "none":
        out["spin_decay_time"] = None
    else:
        out["spin_decay_time"] = _fixed(decay, key("spin_decay_time"), u.DIMENSIONLESS,
                                        1e-3, 1e6)
    if "position" in table:
        start = _vector(table["position"], key("position"), u.LENGTH)
        if not start[2] >= 0.0:
            raise InputError(key("position"), f"the launch point is below the ground "
                                              f"(z = {start[2]:g} m < 0)")
        out["start"] = start
    if "wind" in table:
        out["wind"] = _vector(table["wind"], key("wind"), u.SPEED)
    out["scheme"] = _choice(table.get("scheme", "adaptive"), key("scheme"),
                            ("adaptive", "sheet"))
    if "tolerance" in table:
        out["solver"] = SolverSettings(flight_tolerance=_fixed(
            table["tolerance"], key("tolerance"), u.DIMENSIONLESS, *FLIGHT_TOLERANCE_RANGE))
    return FlightSettings(**out)


#: Per-ball settings ``fly_launches`` takes (SI, as ``FlightSettings``).
PER_BALL = ("temperature", "pressure", "relative_humidity", "elevation", "landing_height",
            "drag_scale", "lift_scale", "wind_x", "wind_y", "wind_z")
_PACKED = {"drag_scale": 5, "lift_scale": 6, "wind_x": 9, "wind_y": 10, "wind_z": 11,
           "landing_height": 13}  # rows of pack_params
_AIR = ("temperature", "pressure", "relative_humidity", "elevation")


def params_each(settings: FlightSettings, mass, radius, n, per_ball=None) -> np.ndarray:
    """The kernel's parameters of ``n`` balls (``float64[14, n]``, columns as
    ``mcbat.core.flight.pack_params``): ``settings`` with the values of ``per_ball``
    (a mapping of ``PER_BALL`` names to arrays of ``n``, SI) replaced ball by ball.
    The air density follows each ball's temperature, pressure, humidity and elevation."""
    per_ball = {} if per_ball is None else dict(per_ball)
    unknown = sorted(set(per_ball) - set(PER_BALL))
    if unknown:
        raise InputError(unknown[0], f"not a per-ball flight setting (one of "
                         f"{', '.join(PER_BALL)})")
    params = np.repeat(pack_params(settings.params(mass, radius))[:, None], n, 1)
    values = {k: np.broadcast_to(np.asarray(v, float), (n,)) for k, v in per_ball.items()}
    for key, row in _PACKED.items():
        if key in values:
            params[row] = values[key]
    if any(k in values for k in _AIR):
        air = [values.get(k, np.full(n, getattr(settings, k))) for k in _AIR]
        density = np.array([air_density(t - 273.15, p, h, e) for t, p, h, e in zip(*air)])
        params[0] = density * math.pi * radius * radius / (2.0 * mass)
    return np.ascontiguousarray(params)


def fly_launches(settings: FlightSettings, mass, radius, launch_speed, launch_angle,
                 spray_angle, backspin, sidespin, gyrospin=0.0, elevation=None,
                 landing_height=None, per_ball=None):
    """Fly many balls with the batch kernel, each in its own air if asked: a park's
    elevation, a game's weather and wind, a season's drag and lift.

    Parameters
    ----------
    settings : FlightSettings
        Atmosphere, model, launch point, ...; what ``per_ball`` (or ``elevation``,
        ``landing_height``) gives is replaced ball by ball.
    mass, radius : float
        The ball (kg, m).
    launch_speed, launch_angle, spray_angle, backspin, sidespin, gyrospin : array_like
        SI (m/s, rad, rad/s), one value per ball (or scalars).
    elevation, landing_height : array_like, optional
        m, per ball (shorthands for the same keys of ``per_ball``).
    per_ball : mapping of str -> array_like, optional
        Any of ``PER_BALL`` (SI: K, Pa, %, m, m, 1, 1, m/s), per ball.

    Returns
    -------
    out : dict of str -> ndarray
        ``mcbat.core.flight.FLIGHT_FIELDS`` (SI), per ball.
    status : ndarray of int8
        The kernel's status per ball (0 ok; ``mcbat/core/flight/README.md``).
    """
    speed = np.atleast_1d(np.asarray(launch_speed, float))
    n = speed.size
    velocity, spin, start = _launch_arrays(settings, speed, launch_angle, spray_angle,
                                           backspin, sidespin, gyrospin)
    per_ball = _with_shorthands(per_ball, elevation, landing_height)
    out, status = fly_balls_each(params_each(settings, mass, radius, n, per_ball), start,
                                 velocity, spin)
    return {name: out[i] for i, name in enumerate(FLIGHT_FIELDS)}, status


def heights_at_distance(settings: FlightSettings, mass, radius, distance, launch_speed,
                        launch_angle, spray_angle, backspin, sidespin, gyrospin=0.0,
                        per_ball=None):
    """Height (m) and spray angle (rad) of each ball where its horizontal distance from
    home plate first reaches ``distance`` (m, per ball): where it meets a fence standing
    there; NaN where it comes down before. Arguments as ``fly_launches``."""
    speed = np.atleast_1d(np.asarray(launch_speed, float))
    n = speed.size
    velocity, spin, start = _launch_arrays(settings, speed, launch_angle, spray_angle,
                                           backspin, sidespin, gyrospin)
    out = heights_at_distance_each(params_each(settings, mass, radius, n, per_ball), start,
                                   velocity, spin,
                                   np.ascontiguousarray(np.broadcast_to(
                                       np.asarray(distance, float), (n,))))
    return out[0], out[1]


def _with_shorthands(per_ball, elevation, landing_height):
    per_ball = {} if per_ball is None else dict(per_ball)
    if elevation is not None:
        per_ball["elevation"] = elevation
    if landing_height is not None:
        per_ball["landing_height"] = landing_height
    return per_ball


def _launch_arrays(settings, speed, launch_angle, spray_angle, backspin, sidespin,
                   gyrospin):
    n = speed.size
    v, w = launch_vectors(speed, *(np.broadcast_to(np.asarray(a, float), (n,)) for a in
                                   (launch_angle, spray_angle, backspin, sidespin, gyrospin)))
    velocity = np.ascontiguousarray(np.stack(v))
    spin = np.ascontiguousarray(np.stack(w))
    start = np.ascontiguousarray(np.repeat(np.asarray(settings.start, float)[:, None], n, 1))
    return velocity, spin, start
