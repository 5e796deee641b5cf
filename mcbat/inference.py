"""The spin of measured batted balls, inferred through the game model.

Statcast measures a ball in play's launch speed, launch angle and spray angle, and the
pitch; it publishes no batted-ball spin. :func:`infer_spin` finds, for each ball, the
contact that reproduces the three measured numbers with the measured pitch through
mcbat's game model (``docs/batting.md``), and reports the spin that contact gives
(``docs/spin_inference.md``; equations in ``mcbat/core/contact_inference/README.md``).

Example
-------
>>> import pandas as pd
>>> from mcbat.inference import infer_spin
>>> balls = pd.DataFrame({
...     "pitch_speed": [86.0], "vertical_approach_angle": [-5.0],
...     "horizontal_approach_angle": [0.0], "spin_rate": [2300.0], "spin_axis": [210.0],
...     "handedness": ["R"], "launch_speed": [102.0], "launch_angle": [27.0],
...     "spray_angle": [-10.0]})
>>> out = infer_spin(balls)
>>> out.loc[0, "inference_status"]
'converged'
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from mcbat.bodies import BALL_PRESETS, Ball, Bat, bat_preset
from mcbat.bodies.game import DEFAULT_PIVOT, GAME_RESTITUTION, Restitution, location_table
from mcbat.checks import check_real as _real
from mcbat.checks import check_tolerance
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.core.contact_inference import (
    INFER_BAT_SPEED,
    INFER_FROM_BARREL_END,
    INFERENCE_STATUS_NAMES,
    SOLUTION_FIELDS,
    InferenceSettings,
    allocate_inference_outputs,
    infer_contact_batch,
)
from mcbat.core.geometry import profile_table
from mcbat.core.swing import GAME_INPUT_FIELDS, SWEET_SPOT_FROM_BARREL_END
from mcbat.dataset.schema import derive_game
from mcbat.errors import InputError

__all__ = ["CARRIED_COLUMNS", "INPUT_COLUMNS", "METADATA_KEY", "OPTIONAL_COLUMNS",
           "OUTPUT_UNITS", "STATUS_NAMES", "InferenceOptions", "SpinAssumptions", "infer_spin",
           "predict_batted_balls", "write"]

_MPH = 0.44704
_RPM = 60.0 / (2.0 * math.pi)
_DEG = math.pi / 180.0

INPUT_COLUMNS = {
    "pitch_speed": "mph", "vertical_approach_angle": "deg",
    "horizontal_approach_angle": "deg", "spin_rate": "rpm", "handedness": "R/L",
    "launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
}
"""Required columns (Statcast's tidy names, ``mcbat.statcast.read``) and their units: the
pitch at the plate (speed, approach angles: vertical < 0 descending, horizontal > 0
moving towards first base; spin rate), the batter's side, and the batted ball."""

OPTIONAL_COLUMNS = {"spin_axis": "deg", "bat_speed": "mph", "attack_angle": "deg",
                    "attack_direction": "deg"}
"""Optional columns. ``spin_axis`` (Statcast's clock-face convention, 180 = pure
backspin; NaN or absent: :attr:`SpinAssumptions.spin_axis`); ``bat_speed`` (where
finite, used, and the contact position inferred instead); ``attack_angle`` (where
finite, used instead of :attr:`SpinAssumptions.attack_angle`); ``attack_direction`` is
accepted but not used: it is one of the unknowns that reproduce the spray angle
(``docs/spin_inference.md``)."""

STATUS_NAMES = (*INFERENCE_STATUS_NAMES.values(), "missing_input")
"""Values of the ``inference_status`` column: ``missing_input`` for a row with a NaN in
a required column (with ``missing="flag"``)."""

OUTPUT_UNITS = {
    "inference_status": "", "inferred": "", "backspin": "rpm", "sidespin": "rpm",
    "gyrospin": "rpm", "spin_rate": "rpm", "undercut": "m", "bat_speed": "mph",
    "from_barrel_end": "m", "attack_direction": "deg", "attack_angle": "deg",
    "collision_efficiency": "1", "inference_iterations": "", "kernel_evaluations": "",
}
"""Columns of :func:`infer_spin`'s result and their units."""


@dataclass(frozen=True)
class SpinAssumptions:
    """What the measurements leave open, assumed (SI: m, rad; defaults: the game
    presets, ``docs/batting.md``; their effect on the spin: ``docs/spin_inference.md``).

    ``attack_angle`` (rad) is used where the table has no measured one;
    ``vertical_bat_angle`` (rad, < 0 barrel below the hands) and ``pivot`` (m from the
    knob) always; ``from_barrel_end`` (m) where the bat speed is inferred. ``mu``,
    ``restitution`` (``e*`` and ``e_x``), the bat and ball; the pitch's
    ``spin_efficiency`` and ``gyro_sign``, and its ``spin_axis`` (rad, Statcast's
    convention) where the table has none. ``contact_side``: where the bat speed is
    measured, the launch speed has two contact positions, one on each side of its
    maximum along the bat: ``"handle"`` (default) or ``"end"``.
    """

    bat: Bat = dataclasses.field(default_factory=lambda: bat_preset("r161"))
    ball: Ball = BALL_PRESETS["baseball"]
    attack_angle: float = 10.0 * _DEG
    vertical_bat_angle: float = -30.0 * _DEG
    pivot: float = DEFAULT_PIVOT
    from_barrel_end: float = SWEET_SPOT_FROM_BARREL_END
    mu: float = 0.5
    restitution: Restitution = GAME_RESTITUTION
    spin_efficiency: float = 1.0
    gyro_sign: float = 1.0
    spin_axis: float = math.pi
    contact_side: str = "handle"

    def __post_init__(self):
        bat = self.bat
        if bat.length is None or bat.cm_from_barrel_end is None:
            raise InputError("bat", "needs the bat's length and CM (cm_from_knob), or a "
                             "bat preset")
        for name in ("attack_angle", "vertical_bat_angle"):
            value = _real(getattr(self, name), name)
            if not abs(value) < math.pi / 2:
                raise InputError(name, f"must lie within (-90, 90) deg, got "
                                 f"{math.degrees(value):.6g} deg (angles are in rad)")
        sweet = bat.length - SWEET_SPOT_FROM_BARREL_END
        if not 0.0 <= _real(self.pivot, "pivot") < sweet:
            raise InputError("pivot", f"must lie between the knob and the sweet spot "
                             f"([0, {sweet:.4g}) m from the knob), got {self.pivot!r}")
        if not 0.0 <= _real(self.from_barrel_end, "from_barrel_end") <= sweet:
            raise InputError("from_barrel_end", f"must lie within [0, {sweet:.4g}] m, got "
                             f"{self.from_barrel_end!r}")
        _real(self.mu, "mu", minimum=0.0)
        _real(self.spin_efficiency, "spin_efficiency", minimum=0.0, maximum=1.0)
        if self.gyro_sign not in (1, -1):
            raise InputError("gyro_sign", f"must be +1 or -1, got {self.gyro_sign!r}")
        _real(self.spin_axis, "spin_axis")
        if self.contact_side not in ("handle", "end"):
            raise InputError("contact_side", f'must be "handle" or "end", got '
                             f"{self.contact_side!r}")

    def config(self) -> dict:
        """As plain data (for ``df.attrs``): angles in deg, lengths in m."""
        return {"bat": self.bat.preset or "custom", "ball": "custom" if self.ball !=
                BALL_PRESETS["baseball"] else "baseball",
                "attack_angle_deg": math.degrees(self.attack_angle),
                "vertical_bat_angle_deg": math.degrees(self.vertical_bat_angle),
                "pivot_m": self.pivot, "from_barrel_end_m": self.from_barrel_end,
                "mu": self.mu, "restitution": self.restitution.config(),
                "spin_efficiency": self.spin_efficiency, "gyro_sign": self.gyro_sign,
                "spin_axis_deg": math.degrees(self.spin_axis),
                "contact_side": self.contact_side}


@dataclass(frozen=True)
class InferenceOptions:
    """The Newton iteration (``mcbat/core/contact_inference/README.md``): at most
    ``max_iterations``; converged when the launch speed is matched to ``tolerance``
    (relative) and the angles to ``tolerance`` rad; the impact kernel's accuracy
    (``steps``, ``impact_tolerance``, ``max_steps``: as :class:`mcbat.api.SolverSettings`);
    the unknowns' bounds: bat speed (mph), attack direction (deg), contact position (m
    from the barrel end), and the contact azimuth ``|theta|`` (deg; the undercut is
    ``reach sin(theta)``)."""

    max_iterations: int = 30
    tolerance: float = 1e-9
    steps: int = DEFAULT_STEPS
    impact_tolerance: float = DEFAULT_TOLERANCE
    max_steps: int = DEFAULT_MAX_STEPS
    bat_speed_range: tuple[float, float] = (25.0, 110.0)
    attack_direction_max: float = 80.0
    from_barrel_end_range: tuple[float, float] = (0.0, 0.4)
    contact_angle_max: float = 60.0

    def __post_init__(self):
        check_tolerance(_real(self.impact_tolerance, "impact_tolerance"), "impact_tolerance")
        if not (isinstance(self.max_iterations, int) and 1 <= self.max_iterations <= 1000):
            raise InputError("max_iterations", f"must be an integer in [1, 1000], got "
                             f"{self.max_iterations!r}")
        if not 0.0 < _real(self.tolerance, "tolerance") < 1e-3:
            raise InputError("tolerance", f"must lie in (0, 1e-3), got {self.tolerance!r}")
        lo, hi = (_real(v, "bat_speed_range") for v in self.bat_speed_range)
        if not 0.0 < lo < hi:
            raise InputError("bat_speed_range", f"must be 0 < low < high mph, got "
                             f"{self.bat_speed_range!r}")
        lo, hi = (_real(v, "from_barrel_end_range") for v in self.from_barrel_end_range)
        if not 0.0 <= lo < hi:
            raise InputError("from_barrel_end_range", f"must be 0 <= low < high m, got "
                             f"{self.from_barrel_end_range!r}")
        if not 0.0 < _real(self.attack_direction_max, "attack_direction_max") < 90.0:
            raise InputError("attack_direction_max", "must lie in (0, 90) deg")
        if not 0.0 < _real(self.contact_angle_max, "contact_angle_max") < 90.0:
            raise InputError("contact_angle_max", "must lie in (0, 90) deg")

    def kernel_settings(self, contact_side: str) -> InferenceSettings:
        """As the jitted kernel's named tuple (SI)."""
        return InferenceSettings(
            int(self.max_iterations), float(self.tolerance), int(self.steps),
            float(self.impact_tolerance), int(self.max_steps),
            1.0 if contact_side == "handle" else -1.0,
            float(self.bat_speed_range[0]) * _MPH, float(self.bat_speed_range[1]) * _MPH,
            float(self.attack_direction_max) * _DEG, float(self.from_barrel_end_range[0]),
            float(self.from_barrel_end_range[1]), float(self.contact_angle_max) * _DEG)


def _column(table, name, n, required=True):
    """A column as an array (None if optional and absent)."""
    if name not in table:
        if required:
            raise InputError(name, "missing column (infer_spin needs: "
                             f"{', '.join(INPUT_COLUMNS)})")
        return None
    values = np.asarray(table[name])
    if values.shape != (n,):
        raise InputError(name, f"must be a 1-D column of {n} values, got shape "
                         f"{values.shape}")
    return values


def _numeric(table, name, n, required=True):
    values = _column(table, name, n, required)
    if values is None:
        return None
    try:
        values = values.astype(np.float64)
    except (TypeError, ValueError):
        raise InputError(name, f"must be numbers, got dtype {values.dtype}") from None
    bad = np.isinf(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(name, f"must be finite (or NaN where missing), got "
                         f"{float(values[i])!r} in row {i}")
    return values


def _check_range(values, name, ok, what):
    bad = ~ok(values) & ~np.isnan(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(name, f"{what}, got {float(values[i])!r} in row {i}")


_RANGES = {
    "pitch_speed": (lambda v: v > 0.0, "must be > 0 mph"),
    "vertical_approach_angle": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "horizontal_approach_angle": (lambda v: np.abs(v) < 90.0,
                                  "must lie within (-90, 90) deg"),
    "spin_rate": (lambda v: v >= 0.0, "must be >= 0 rpm"),
    "launch_speed": (lambda v: v > 0.0, "must be > 0 mph"),
    "launch_angle": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "spray_angle": (lambda v: np.abs(v) <= 180.0, "must lie within [-180, 180] deg"),
    "bat_speed": (lambda v: v > 0.0, "must be > 0 mph"),
    "attack_angle": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "attack_direction": (lambda v: np.abs(v) < 90.0, "must lie within (-90, 90) deg"),
    "spin_axis": (lambda v: np.abs(v) <= 360.0, "must lie within [-360, 360] deg"),
}


def _bat_table(bat: Bat):
    if bat.profile is not None:
        return bat.profile.kernel_table
    knob = -(bat.length - bat.cm_from_barrel_end)
    return profile_table(np.array([knob, bat.cm_from_barrel_end]),
                         np.array([[0.0], [0.0], [0.0], [float(bat.radius)]]),
                         np.zeros((3, 1)))


def infer_spin(table, *, assumptions: SpinAssumptions | None = None,
               options: InferenceOptions | None = None, missing: str = "flag",
               use_bat_speed: bool = True, use_attack_angle: bool = True) -> pd.DataFrame:
    """Infer the contact and the spin of measured batted balls.

    Parameters
    ----------
    table : pandas.DataFrame or mapping of column name -> 1-D array
        :data:`INPUT_COLUMNS` (Statcast names and units, as ``mcbat.statcast.read`` gives
        them), and any of :data:`OPTIONAL_COLUMNS`.
    assumptions : SpinAssumptions, optional
        What the data leave open (default: the game presets).
    options : InferenceOptions, optional
        The iteration's settings and the unknowns' bounds.
    missing : {"flag", "raise"}
        A NaN in a required column: the row gets ``inference_status = "missing_input"``
        and NaN outputs ("flag"), or :class:`~mcbat.errors.InputError` naming the column
        ("raise").
    use_bat_speed, use_attack_angle : bool
        Use the measured ``bat_speed`` / ``attack_angle`` where the table has them
        (False: infer the bat speed / assume the attack angle for every ball).

    Returns
    -------
    pandas.DataFrame
        Same index as ``table`` (a range index for a mapping); the columns of
        :data:`OUTPUT_UNITS`: ``inference_status`` (:data:`STATUS_NAMES`), ``inferred``
        (``"bat_speed"`` or ``"from_barrel_end"``), the batted ball's ``backspin``,
        ``sidespin``, ``gyrospin``, ``spin_rate`` (rpm, ``docs/batting.md``), the contact
        (``undercut``, ``bat_speed``, ``from_barrel_end``, ``attack_direction``,
        ``attack_angle``), ``collision_efficiency``, ``inference_iterations`` and
        ``kernel_evaluations`` (game-kernel calls, the cost). NaN
        wherever the status is not ``converged``. ``df.attrs``: ``units``,
        ``assumptions``, ``status_counts``.

    Raises
    ------
    InputError
        Naming the column: a required one missing, a non-numeric or infinite value, a
        value out of range, a handedness other than "R"/"L"; or naming the setting.
    """
    assumptions = SpinAssumptions() if assumptions is None else assumptions
    options = InferenceOptions() if options is None else options
    if missing not in ("flag", "raise"):
        raise InputError("missing", f'must be "flag" or "raise", got {missing!r}')
    if not isinstance(table, pd.DataFrame | Mapping):
        raise InputError("table", f"must be a DataFrame or a mapping of columns, got "
                         f"{type(table).__name__}")
    for name in INPUT_COLUMNS:
        if name not in table:
            raise InputError(name, "missing column (infer_spin needs: "
                             f"{', '.join(INPUT_COLUMNS)})")
    first = np.asarray(table["launch_speed"])
    if first.ndim != 1:
        raise InputError("launch_speed", f"must be a 1-D column, got shape {first.shape}")
    n = first.shape[0]
    index = table.index if isinstance(table, pd.DataFrame) else pd.RangeIndex(n)

    cols = {name: _numeric(table, name, n) for name in INPUT_COLUMNS if name != "handedness"}
    for name in OPTIONAL_COLUMNS:
        values = _numeric(table, name, n, required=False)
        cols[name] = np.full(n, np.nan) if values is None else values
    for name, (ok, what) in _RANGES.items():
        _check_range(cols[name], name, ok, what)
    hand_raw = _column(table, "handedness", n)
    is_r = hand_raw == "R"
    is_l = hand_raw == "L"
    hand_missing = pd.isna(hand_raw)
    bad = ~(is_r | is_l | hand_missing)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError("handedness", f'must be "R" or "L", got {hand_raw[i]!r} in row {i}')
    missing_rows = hand_missing.copy()
    for name in INPUT_COLUMNS:
        if name == "handedness":
            nan = hand_missing
        else:
            nan = np.isnan(cols[name])
        if missing == "raise" and nan.any():
            i = int(np.flatnonzero(nan)[0])
            raise InputError(name, f"missing value (NaN) in row {i}")
        missing_rows |= nan

    game, mode = _game_inputs(cols, np.where(is_l, -1.0, 1.0), assumptions, n,
                              use_bat_speed, use_attack_angle)
    observed = np.ascontiguousarray(np.stack((cols["launch_speed"] * _MPH,
                                              cols["launch_angle"] * _DEG,
                                              cols["spray_angle"] * _DEG)))
    observed[:, missing_rows] = np.nan
    rest = assumptions.restitution
    loc_z, loc_f = ((np.empty(0), np.empty(0)) if rest.location is None
                    else location_table(rest.location))
    solution, residual, status, iterations, evaluations = allocate_inference_outputs(n)
    if n:
        infer_contact_batch(game, observed, mode, _bat_table(assumptions.bat),
                            np.ascontiguousarray(loc_z, dtype=np.float64),
                            np.ascontiguousarray(loc_f, dtype=np.float64),
                            options.kernel_settings(assumptions.contact_side), solution,
                            residual, status, iterations, evaluations)
    measured = cols["attack_angle"] if use_attack_angle else np.full(n, np.nan)
    attack = np.where(np.isfinite(measured), measured, math.degrees(assumptions.attack_angle))
    out = _result(index, solution, status, iterations, mode, missing_rows, attack,
                  assumptions)
    out["kernel_evaluations"] = np.where(missing_rows, 0, evaluations)
    return out


def predict_batted_balls(table, *, undercut, attack_direction, bat_speed=None,
                         from_barrel_end=None, assumptions: SpinAssumptions | None = None,
                         options: InferenceOptions | None = None) -> pd.DataFrame:
    """The forward model :func:`infer_spin` inverts: the batted balls that given contacts
    give, with the same inputs and assumptions (the game kernel, ``solve_game_batch``).

    Parameters
    ----------
    table : pandas.DataFrame or mapping
        The pitch columns of :data:`INPUT_COLUMNS` and ``handedness`` (the batted-ball
        columns are not needed), optionally ``spin_axis`` and ``attack_angle``.
    undercut : array_like
        m (> 0: the ball's centre passes above the bat axis).
    attack_direction : array_like
        deg, positive towards the batter's opposite field.
    bat_speed : array_like, optional
        mph; default: the table's ``bat_speed``.
    from_barrel_end : array_like, optional
        m; default: :attr:`SpinAssumptions.from_barrel_end`.

    Returns
    -------
    pandas.DataFrame
        ``status`` (the game kernel's, ``"ok"`` when solved), ``launch_speed`` (mph),
        ``launch_angle``, ``spray_angle`` (deg), ``backspin``, ``sidespin``,
        ``gyrospin``, ``spin_rate`` (rpm), ``collision_efficiency``; same index as
        ``table``.
    """
    from mcbat.core import status as st
    from mcbat.core.swing import allocate_game_outputs, solve_game_batch
    from mcbat.core.swing.game import GAME_OUTPUT_FIELDS

    assumptions = SpinAssumptions() if assumptions is None else assumptions
    options = InferenceOptions() if options is None else options
    needed = {k: v for k, v in INPUT_COLUMNS.items() if not k.startswith(("launch", "spray"))}
    for name in needed:
        if name not in table:
            raise InputError(name, "missing column")
    n = np.asarray(table["pitch_speed"]).shape[0]
    index = table.index if isinstance(table, pd.DataFrame) else pd.RangeIndex(n)
    cols = {name: _numeric(table, name, n) for name in needed if name != "handedness"}
    for name in OPTIONAL_COLUMNS:
        values = _numeric(table, name, n, required=False)
        cols[name] = np.full(n, np.nan) if values is None else values
    if bat_speed is not None:
        cols["bat_speed"] = np.broadcast_to(np.asarray(bat_speed, np.float64), (n,)).copy()
    hand = _column(table, "handedness", n)
    if not np.isin(hand, ["R", "L"]).all():
        raise InputError("handedness", 'must be "R" or "L"')
    game, _ = _game_inputs(cols, np.where(hand == "L", -1.0, 1.0), assumptions, n, True,
                           True)
    z = (np.full(n, assumptions.from_barrel_end) if from_barrel_end is None
         else np.broadcast_to(np.asarray(from_barrel_end, np.float64), (n,)).copy())
    bat = assumptions.bat
    radius, slope = bat.surface(np.asarray(bat.clip_axial(bat.cm_from_barrel_end - z)))
    rows = {name: i for i, name in enumerate(GAME_INPUT_FIELDS)}
    game[rows["from_barrel_end"]] = z
    game[rows["bat_radius"]] = radius
    game[rows["bat_slope"]] = slope
    game[rows["e_location_factor"]] = assumptions.restitution.location_factor(z)
    game[rows["undercut"]] = np.broadcast_to(np.asarray(undercut, np.float64), (n,))
    game[rows["attack_direction"]] = np.broadcast_to(
        np.asarray(attack_direction, np.float64), (n,)) * _DEG
    frame, out, game_out, status, end_state = allocate_game_outputs(n)
    solve_game_batch(game, options.steps, options.impact_tolerance, options.max_steps, frame,
                     out, game_out, status, end_state)
    go = dict(zip(GAME_OUTPUT_FIELDS, game_out))
    ball = derive_game((go["field_ball_vx"], go["field_ball_vy"], go["field_ball_vz"]),
                       (go["field_ball_wx"], go["field_ball_wy"], go["field_ball_wz"]))
    names = np.array([st.STATUS_NAMES[int(c)] for c in status], dtype=object)
    return pd.DataFrame({"status": names, **ball,
                         "collision_efficiency": go["collision_efficiency"]}, index=index)


def _game_inputs(cols, hand, a: SpinAssumptions, n, use_bat_speed, use_attack_angle):
    """The game kernel's inputs (:data:`GAME_INPUT_FIELDS`, SI) and the mode per ball."""
    bat, ball, rest = a.bat, a.ball, a.restitution
    bat_speed = cols["bat_speed"] if use_bat_speed else np.full(n, np.nan)
    measured = np.isfinite(bat_speed)
    mode = np.where(measured, INFER_FROM_BARREL_END, INFER_BAT_SPEED).astype(np.int8)
    attack = cols["attack_angle"] if use_attack_angle else np.full(n, np.nan)
    attack = np.where(np.isfinite(attack), attack * _DEG, a.attack_angle)
    axis = np.where(np.isfinite(cols["spin_axis"]), cols["spin_axis"] * _DEG, a.spin_axis)
    values = {
        "ball_mass": ball.mass, "ball_radius": ball.radius,
        "ball_inertia_factor": ball.inertia_factor, "bat_mass": bat.mass,
        "bat_transverse_inertia": bat.transverse_inertia,
        "bat_axial_inertia": bat.axial_inertia, "bat_length": bat.length,
        "bat_cm_from_knob": bat.length - bat.cm_from_barrel_end,
        "bat_radius": 0.0, "bat_slope": 0.0, "handedness": hand,
        "pitch_speed": cols["pitch_speed"] * _MPH,
        "pitch_vertical_approach_angle": cols["vertical_approach_angle"] * _DEG,
        "pitch_horizontal_approach_angle": cols["horizontal_approach_angle"] * _DEG,
        "pitch_spin_rate": cols["spin_rate"] / _RPM, "pitch_spin_axis": axis,
        "pitch_spin_efficiency": a.spin_efficiency, "pitch_gyro_sign": float(a.gyro_sign),
        "bat_speed": np.where(measured, bat_speed * _MPH, np.nan), "attack_angle": attack,
        "attack_direction": 0.0, "vertical_bat_angle": a.vertical_bat_angle,
        "pivot": a.pivot, "from_barrel_end": a.from_barrel_end, "undercut": 0.0,
        "mu": a.mu, "e_ref": rest.e_ref, "e_slope": rest.e_slope,
        "e_speed_ref": rest.e_speed_ref,
        "e_location_factor": rest.location_factor(a.from_barrel_end), "e_x": rest.e_x,
    }
    game = np.empty((len(GAME_INPUT_FIELDS), n))
    for i, name in enumerate(GAME_INPUT_FIELDS):
        game[i] = values[name]
    return game, mode


def _result(index, solution, status, iterations, mode, missing_rows, attack, a):
    sol = dict(zip(SOLUTION_FIELDS, solution))
    spin = derive_game((sol["field_ball_vx"], sol["field_ball_vy"], sol["field_ball_vz"]),
                       (sol["field_ball_wx"], sol["field_ball_wy"], sol["field_ball_wz"]))
    names = np.array([INFERENCE_STATUS_NAMES[c] for c in sorted(INFERENCE_STATUS_NAMES)],
                     dtype=object)
    status_names = names[status.astype(np.int64)]
    status_names[missing_rows] = "missing_input"
    ok = status_names == "converged"
    attack = np.where(ok, attack, np.nan)
    out = pd.DataFrame({
        "inference_status": pd.Categorical(status_names, categories=list(STATUS_NAMES)),
        "inferred": pd.Categorical(np.where(mode == INFER_BAT_SPEED, "bat_speed",
                                            "from_barrel_end"),
                                   categories=["bat_speed", "from_barrel_end"]),
        "backspin": spin["backspin"], "sidespin": spin["sidespin"],
        "gyrospin": spin["gyrospin"], "spin_rate": spin["spin_rate"],
        "undercut": sol["undercut"], "bat_speed": sol["bat_speed"] / _MPH,
        "from_barrel_end": sol["from_barrel_end"],
        "attack_direction": np.degrees(sol["attack_direction"]), "attack_angle": attack,
        "collision_efficiency": sol["collision_efficiency"],
        "inference_iterations": np.where(missing_rows, 0, iterations),
    }, index=index)
    out.attrs["units"] = dict(OUTPUT_UNITS)
    out.attrs["assumptions"] = a.config()
    out.attrs["status_counts"] = {name: int((status_names == name).sum())
                                  for name in STATUS_NAMES}
    return out


CARRIED_COLUMNS = ("game_pk", "at_bat_number", "pitch_number", "batter", "pitcher",
                   "game_date", "home_team", "elevation", "handedness", "pitch_type",
                   "events", "bb_type", "launch_speed", "launch_angle", "spray_angle",
                   "hit_distance_sc")
"""Columns of the tidy table :func:`write` keeps beside the inference's (those present)."""

METADATA_KEY = b"mcbat.inference"
"""The Parquet schema-metadata key of :func:`write`'s file: JSON with ``units``,
``assumptions`` and ``status_counts``."""


def write(table, spin, path) -> None:
    """Write the balls (:data:`CARRIED_COLUMNS` of ``table``) and their inferred contact
    and spin (``spin``, from :func:`infer_spin` on ``table``) to one Parquet file,
    atomically, with units, assumptions and status counts in the schema metadata."""
    import json
    import os
    from pathlib import Path

    import pyarrow as pa
    import pyarrow.parquet as pq

    carried = [c for c in CARRIED_COLUMNS if c in table.columns]
    df = pd.concat([table[carried], spin], axis=1)
    units = {c: table.attrs.get("units", {}).get(c, "") for c in carried}
    units.update(spin.attrs["units"])
    info = {"units": units, "assumptions": spin.attrs["assumptions"],
            "status_counts": spin.attrs["status_counts"]}
    arrow = pa.Table.from_pandas(df, preserve_index=False)
    arrow = arrow.replace_schema_metadata({**(arrow.schema.metadata or {}),
                                           METADATA_KEY: json.dumps(info).encode()})
    path = Path(os.fspath(path))
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        pq.write_table(arrow, tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
