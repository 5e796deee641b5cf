"""The inference itself: ``infer_spin`` (the contact, hence the spin, behind each
measured ball, by the jitted Newton solver of ``mcbat.core.contact_inference``) and
``predict_batted_balls``, the forward model it inverts."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

from mcbat.bodies import Bat
from mcbat.bodies.restitution import location_table
from mcbat.core.geometry import profile_table
from mcbat.core.units import M_S_PER_MPH, RAD_PER_DEG, RPM_PER_RAD_S
from mcbat.errors import InputError
from mcbat.inference.assumptions import InferenceOptions, SpinAssumptions
from mcbat.inference.columns import (
    INPUT_COLUMNS,
    OPTIONAL_COLUMNS,
    OUTPUT_UNITS,
    RANGES,
    SPRAY_BEHIND,
    STATUS_NAMES,
    SWING_COLUMNS,
    bunt_rows,
    check_range,
    numeric_column,
    read_column,
    swing_column,
    unusable_swing_rows,
)
from mcbat.inference.nodes import attack_angle_nodes, combine, posterior_weight
from mcbat.solving import GAME_INPUT_FIELDS, GAME_OUTPUT_FIELDS, solve_games
from mcbat.solving.derived import derive_game
from mcbat.solving.inference import (
    INFER_BAT_SPEED,
    INFER_FROM_BARREL_END,
    INFER_NEAREST_BAT_SPEED,
    INFERENCE_STATUS_NAMES,
    SOLUTION_FIELDS,
    InferenceStatus,
    infer_contacts,
)
from mcbat.study.swing_plane import fill_vertical_bat_angle, measured_tilt

__all__ = ["infer_spin", "predict_batted_balls"]



def _bat_table(bat: Bat):
    if bat.profile is not None:
        return bat.profile.kernel_table
    knob = -(bat.length - bat.cm_from_barrel_end)
    return profile_table(np.array([knob, bat.cm_from_barrel_end]),
                         np.array([[0.0], [0.0], [0.0], [float(bat.radius)]]),
                         np.zeros((3, 1)))


def infer_spin(table, *, assumptions: SpinAssumptions | None = None,
               options: InferenceOptions | None = None, missing: str = "flag",
               use_bat_speed: bool = True, use_attack_angle: bool = True,
               use_swing_plane: bool = True) -> pd.DataFrame:
    """Infer the contact and the spin of measured batted balls.

    Parameters
    ----------
    table : pandas.DataFrame or mapping of column name -> 1-D array
        ``INPUT_COLUMNS`` (Statcast names and units, as ``mcbat.statcast.read`` gives
        them), and any of ``OPTIONAL_COLUMNS``.
    assumptions : SpinAssumptions, optional
        What the data leave open (default: the game presets).
    options : InferenceOptions, optional
        The iteration's settings and the unknowns' bounds.
    missing : {"flag", "raise"}
        A NaN in a required column: the row gets ``inference_status = "missing_input"``
        and NaN outputs ("flag"), or ``mcbat.errors.InputError`` naming the column
        ("raise").
    use_bat_speed, use_attack_angle : bool
        Use the measured ``bat_speed`` / ``attack_angle`` where the table has them
        (False: infer the bat speed / assume the attack angle for every ball).
    use_swing_plane : bool
        Where the table has a ``swing_path_tilt``, take the ball's vertical bat angle from
        it and the attack angle (``mcbat.study.swing_plane``); else, and with False,
        ``SpinAssumptions.vertical_bat_angle``.

    Returns
    -------
    pandas.DataFrame
        Same index as ``table`` (a range index for a mapping); the columns of
        ``OUTPUT_UNITS``: ``inference_status`` (``STATUS_NAMES``), ``inferred``
        (``"bat_speed"`` or ``"from_barrel_end"``), the batted ball's ``backspin``,
        ``sidespin``, ``gyrospin``, ``spin_rate`` (rpm, ``docs/batting.md``), the contact
        (``undercut``, ``bat_speed``, ``from_barrel_end``, ``attack_direction``,
        ``attack_angle``), ``collision_efficiency``, ``inference_iterations``,
        ``kernel_evaluations`` (game-kernel calls, the cost) and ``spray_observed``
        (False for a ball fielded behind the plate's line, ``SPRAY_BEHIND``: solved with
        a straightaway launch). NaN wherever the status is not ``converged``.
        ``df.attrs``: ``units``, ``assumptions``, ``status_counts``, ``swing_plane`` (the
        balls whose bat angle came from their measured swing plane).

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

    cols = {name: numeric_column(table, name, n) for name in INPUT_COLUMNS if name != "handedness"}
    for name in OPTIONAL_COLUMNS:
        if name in SWING_COLUMNS:
            continue
        values = numeric_column(table, name, n, required=False)
        cols[name] = np.full(n, np.nan) if values is None else values
    for name, (ok, what) in RANGES.items():
        check_range(cols[name], name, ok, what)
    reasons = _swing(table, n, cols, options.bat_speed_floor)
    unusable = np.any(list(reasons.values()), axis=0)
    hand_raw = read_column(table, "handedness", n)
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

    unusable &= ~missing_rows
    game, mode = _game_inputs(cols, np.where(is_l, -1.0, 1.0), assumptions, n,
                              use_bat_speed, use_attack_angle)
    tilt = measured_tilt(cols["swing_path_tilt"], slice(None)) if use_swing_plane else None
    if options.bat_speed_error > 0.0:
        mode[mode == INFER_FROM_BARREL_END] = INFER_NEAREST_BAT_SPEED
    spray_observed = ~(np.abs(cols["spray_angle"]) > SPRAY_BEHIND)
    observed = np.ascontiguousarray(np.stack((
        cols["launch_speed"] * M_S_PER_MPH, cols["launch_angle"] * RAD_PER_DEG,
        np.where(spray_observed, cols["spray_angle"], 0.0) * RAD_PER_DEG)))
    skipped = missing_rows | unusable
    observed[:, skipped] = np.nan
    rest = assumptions.restitution
    loc_z, loc_f = ((np.empty(0), np.empty(0)) if rest.location is None
                    else location_table(rest.location))
    measured = cols["attack_angle"] if use_attack_angle else np.full(n, np.nan)
    nodes = attack_angle_nodes(measured, assumptions, options.attack_angle_nodes)
    runs = _run_nodes(game, observed, mode, nodes, cols["bat_speed"], assumptions, options,
                      loc_z, loc_f, tilt)
    solution, status, iterations, evaluations, adjustment, inconsistent, attack = combine(
        runs, assumptions)
    inconsistent &= ~skipped
    if len(nodes) == 1:  # the measured value itself, not its round trip through rad
        attack = np.where(np.isfinite(measured), measured,
                          math.degrees(assumptions.attack_angle))
    out = _result(index, solution, status, iterations, mode, skipped, attack,
                  assumptions,
                  {"missing_input": missing_rows, "unusable_swing": unusable,
                   "bat_speed_inconsistent": inconsistent}, adjustment)
    out["kernel_evaluations"] = np.where(skipped, 0, evaluations)
    out["spray_observed"] = spray_observed
    out.attrs["unusable_swing"] = {k: int((v & unusable).sum()) for k, v in reasons.items()}
    out.attrs["swing_plane"] = 0 if tilt is None else int((np.isfinite(tilt) & ~skipped).sum())
    return out


def predict_batted_balls(table, *, undercut, attack_direction, bat_speed=None,
                         from_barrel_end=None, assumptions: SpinAssumptions | None = None,
                         options: InferenceOptions | None = None) -> pd.DataFrame:
    """The forward model ``infer_spin`` inverts: the batted balls that given contacts
    give, with the same inputs and assumptions (the game kernel, ``solve_game_batch``).

    Parameters
    ----------
    table : pandas.DataFrame or mapping
        The pitch columns of ``INPUT_COLUMNS`` and ``handedness`` (the batted-ball
        columns are not needed), optionally ``spin_axis``, ``attack_angle`` and
        ``swing_path_tilt`` (as ``infer_spin`` uses them).
    undercut : array_like
        m (> 0: the ball's centre passes above the bat axis).
    attack_direction : array_like
        deg, positive towards the batter's opposite field.
    bat_speed : array_like, optional
        mph; default: the table's ``bat_speed``.
    from_barrel_end : array_like, optional
        m; default: ``SpinAssumptions.from_barrel_end``.

    Returns
    -------
    pandas.DataFrame
        ``status`` (the game kernel's, ``"ok"`` when solved), ``launch_speed`` (mph),
        ``launch_angle``, ``spray_angle`` (deg), ``backspin``, ``sidespin``,
        ``gyrospin``, ``spin_rate`` (rpm), ``collision_efficiency``; same index as
        ``table``.
    """
    from mcbat.core import status as st

    assumptions = SpinAssumptions() if assumptions is None else assumptions
    options = InferenceOptions() if options is None else options
    needed = {k: v for k, v in INPUT_COLUMNS.items() if not k.startswith(("launch", "spray"))}
    for name in needed:
        if name not in table:
            raise InputError(name, "missing column")
    n = np.asarray(table["pitch_speed"]).shape[0]
    index = table.index if isinstance(table, pd.DataFrame) else pd.RangeIndex(n)
    cols = {name: numeric_column(table, name, n) for name in needed if name != "handedness"}
    for name in OPTIONAL_COLUMNS:
        values = numeric_column(table, name, n, required=False)
        cols[name] = np.full(n, np.nan) if values is None else values
    if bat_speed is not None:
        cols["bat_speed"] = np.broadcast_to(np.asarray(bat_speed, np.float64), (n,)).copy()
    hand = read_column(table, "handedness", n)
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
    fill_vertical_bat_angle(_swing_rows(game), measured_tilt(cols["swing_path_tilt"],
                                                             slice(None)))
    game[rows["undercut"]] = np.broadcast_to(np.asarray(undercut, np.float64), (n,))
    game[rows["attack_direction"]] = np.broadcast_to(
        np.asarray(attack_direction, np.float64), (n,)) * RAD_PER_DEG
    _, _, game_out, status, _ = solve_games(game, options.solver)
    go = dict(zip(GAME_OUTPUT_FIELDS, game_out))
    ball = derive_game((go["field_ball_vx"], go["field_ball_vy"], go["field_ball_vz"]),
                       (go["field_ball_wx"], go["field_ball_wy"], go["field_ball_wz"]))
    names = np.array([st.STATUS_NAMES[int(c)] for c in status], dtype=object)
    return pd.DataFrame({"status": names, **ball,
                         "collision_efficiency": go["collision_efficiency"]}, index=index)


def _run_nodes(game, observed, mode, nodes, measured_bat_speed, assumptions, options, loc_z,
               loc_f, tilt=None):
    """The inference at each attack-angle node: per node ``(attack angle (rad), weight,
    solution, status, iterations, evaluations, bat-speed adjustment (mph),
    bat_speed_inconsistent)``; the weight is the node's prior weight times the density of
    its contact (``mcbat.inference.nodes.posterior_weight``) where there are several
    nodes. ``tilt`` (rad, NaN where not measured): the swing planes that set each node's
    vertical bat angle."""
    settings = options.kernel_settings(assumptions.contact_side)
    table_ = _bat_table(assumptions.bat)
    loc_z = np.ascontiguousarray(loc_z, dtype=np.float64)
    loc_f = np.ascontiguousarray(loc_f, dtype=np.float64)
    row = GAME_INPUT_FIELDS.index("attack_angle")
    runs = []
    for attack_node, prior in nodes:
        game[row] = attack_node
        if tilt is not None:  # (a ball without a plane keeps the assumed angle)
            fill_vertical_bat_angle(_swing_rows(game), tilt)
        solution, _, status, iterations, evaluations = infer_contacts(
            game, observed, mode, table_, loc_z, loc_f, settings)
        adjustment = np.where(mode == INFER_BAT_SPEED, np.nan,
                              solution[SOLUTION_FIELDS.index("bat_speed")] / M_S_PER_MPH
                              - measured_bat_speed)
        # the z-mode solution carries the measured bat speed itself: exactly 0
        adjustment[np.abs(adjustment) < 1e-9] = 0.0
        converged = status == InferenceStatus.CONVERGED
        inconsistent = converged & (np.abs(adjustment) > options.bat_speed_error)
        if len(nodes) > 1:
            ok = converged & ~inconsistent
            prior = prior * posterior_weight(game, mode, solution, ok, assumptions, options)
        runs.append((attack_node, prior, solution, status, iterations, evaluations,
                     adjustment, inconsistent))
    return runs


def _swing_rows(game) -> dict:
    """The attack and vertical bat angles' rows of the game inputs ``game`` (views)."""
    return {k: game[GAME_INPUT_FIELDS.index(k)] for k in ("attack_angle", "vertical_bat_angle")}


def _swing(table, n, cols, floor):
    """Read the measured swing's columns into ``cols``; why each row's swing is unusable
    (``mcbat.inference.columns.unusable_swing_rows``)."""
    bad_cells = {}
    for name in SWING_COLUMNS:
        cols[name], bad_cells[name] = swing_column(table, name, n)
    return unusable_swing_rows(cols, bad_cells, bunt_rows(table, n), floor)


def _game_inputs(cols, hand, a: SpinAssumptions, n, use_bat_speed, use_attack_angle):
    """The game kernel's inputs (``GAME_INPUT_FIELDS``, SI) and the mode per ball."""
    bat, ball, rest = a.bat, a.ball, a.restitution
    bat_speed = cols["bat_speed"] if use_bat_speed else np.full(n, np.nan)
    measured = np.isfinite(bat_speed)
    mode = np.where(measured, INFER_FROM_BARREL_END, INFER_BAT_SPEED).astype(np.int8)
    attack = cols["attack_angle"] if use_attack_angle else np.full(n, np.nan)
    attack = np.where(np.isfinite(attack), attack * RAD_PER_DEG, a.attack_angle)
    axis = np.where(np.isfinite(cols["spin_axis"]), cols["spin_axis"] * RAD_PER_DEG, a.spin_axis)
    values = {
        "ball_mass": ball.mass, "ball_radius": ball.radius,
        "ball_inertia_factor": ball.inertia_factor, "bat_mass": bat.mass,
        "bat_transverse_inertia": bat.transverse_inertia,
        "bat_axial_inertia": bat.axial_inertia, "bat_length": bat.length,
        "bat_cm_from_knob": bat.length - bat.cm_from_barrel_end,
        "bat_radius": 0.0, "bat_slope": 0.0, "handedness": hand,
        "pitch_speed": cols["pitch_speed"] * M_S_PER_MPH,
        "pitch_vertical_approach_angle": cols["vertical_approach_angle"] * RAD_PER_DEG,
        "pitch_horizontal_approach_angle": cols["horizontal_approach_angle"] * RAD_PER_DEG,
        "pitch_spin_rate": cols["spin_rate"] / RPM_PER_RAD_S, "pitch_spin_axis": axis,
        "pitch_spin_efficiency": a.spin_efficiency, "pitch_gyro_sign": float(a.gyro_sign),
        "bat_speed": np.where(measured, bat_speed * M_S_PER_MPH, np.nan), "attack_angle": attack,
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


def _result(index, solution, status, iterations, mode, skipped, attack, a, flagged,
            adjustment):
    sol = dict(zip(SOLUTION_FIELDS, solution))
    spin = derive_game((sol["field_ball_vx"], sol["field_ball_vy"], sol["field_ball_vz"]),
                       (sol["field_ball_wx"], sol["field_ball_wy"], sol["field_ball_wz"]))
    names = np.array([INFERENCE_STATUS_NAMES[c] for c in sorted(INFERENCE_STATUS_NAMES)],
                     dtype=object)
    status_names = names[status.astype(np.int64)]
    for name, rows in flagged.items():
        status_names[rows] = name
    ok = status_names == "converged"
    attack = np.where(ok, attack, np.nan)
    adjusted = ok & (mode == INFER_NEAREST_BAT_SPEED) & (adjustment != 0.0)
    inferred = np.where(mode == INFER_BAT_SPEED, "bat_speed", "from_barrel_end").astype(object)
    inferred[adjusted] = "nearest_bat_speed"
    keep = lambda values: np.where(ok, values, np.nan)  # noqa: E731
    out = pd.DataFrame({
        "inference_status": pd.Categorical(status_names, categories=list(STATUS_NAMES)),
        "inferred": pd.Categorical(inferred, categories=["bat_speed", "from_barrel_end",
                                                         "nearest_bat_speed"]),
        "backspin": keep(spin["backspin"]), "sidespin": keep(spin["sidespin"]),
        "gyrospin": keep(spin["gyrospin"]), "spin_rate": keep(spin["spin_rate"]),
        "undercut": keep(sol["undercut"]), "bat_speed": keep(sol["bat_speed"] / M_S_PER_MPH),
        "from_barrel_end": keep(sol["from_barrel_end"]),
        "attack_direction": keep(np.degrees(sol["attack_direction"])),
        "attack_angle": attack,
        "collision_efficiency": keep(sol["collision_efficiency"]),
        "bat_speed_adjustment": keep(adjustment),
        "inference_iterations": np.where(skipped, 0, iterations),
    }, index=index)
    out.attrs["units"] = dict(OUTPUT_UNITS)
    out.attrs["assumptions"] = a.config()
    out.attrs["status_counts"] = {name: int((status_names == name).sum())
                                  for name in STATUS_NAMES}
    return out
