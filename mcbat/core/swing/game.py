"""The game kernel: pitch + swing + contact -> bat frame -> ``solve_impact`` -> field frame.

``solve_game_batch`` is a ``prange`` loop over struct-of-arrays, like
``mcbat.core.batch.solve_batch``. Besides the field-frame results it writes the very
bat-frame case it solved (the rows of ``mcbat.core.batch.INPUT_FIELDS``), so every
row can be re-solved in the bat frame alone. Nothing raises inside the loop: a row whose
game inputs cannot be turned into an impact (inconsistent swing angles, an undercut
beyond the reach of ball and barrel, a contact off the bat) gets ``invalid_input``, a
pitch that does not approach the bat ``not_approaching``, with NaN outputs.
"""

import math
from collections import namedtuple

import numba
import numpy as np

from mcbat.core import status as st
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, store_impact
from mcbat.core.cabo2012.contact import Accuracy
from mcbat.core.cabo2012.impact import ImpactInputs, solve_impact
from mcbat.core.geometry import ball_centre_radial_distance
from mcbat.core.jit import njit
from mcbat.core.restitution.forms import energetic_restitution
from mcbat.core.rigid_bodies import relative_contact_velocity
from mcbat.core.swing.frames import (
    BatBody,
    GameContact,
    Pitch,
    Swing,
    bat_frame,
    from_frame,
    pitch_state,
    swing_state,
    to_frame,
)
from mcbat.core.vec3 import dot, norm, scale

__all__ = ["FRAME_FIELDS", "GAME_INPUT", "GAME_INPUT_FIELDS", "GAME_OUTPUT_FIELDS",
           "GAME_ROW_SIGNATURE", "GameInputRows", "allocate_game_outputs", "bat_frame_columns",
           "incoming_state", "solve_game_batch", "solve_game_row"]

GAME_INPUT_FIELDS = (
    "ball_mass", "ball_radius", "ball_inertia_factor",
    "bat_mass", "bat_transverse_inertia", "bat_axial_inertia",
    "bat_length", "bat_cm_from_knob", "bat_radius", "bat_slope",
    "handedness",
    "pitch_speed", "pitch_vertical_approach_angle", "pitch_horizontal_approach_angle",
    "pitch_spin_rate", "pitch_spin_axis", "pitch_spin_efficiency", "pitch_gyro_sign",
    "bat_speed", "attack_angle", "attack_direction", "vertical_bat_angle", "pivot",
    "from_barrel_end", "undercut",
    "mu", "e_ref", "e_slope", "e_speed_ref", "e_location_factor", "e_x",
)
"""Game inputs (SI: m, m/s, rad, rad/s; ``handedness`` +1 R, -1 L). ``bat_radius`` and
``bat_slope`` are the surface at the contact (from a profile, outside the kernel);
``e_location_factor`` is the restitution table's value there (1 without a table)."""

GameInputRows = namedtuple("GameInputRows", GAME_INPUT_FIELDS)
GameInputRows.__doc__ = """The row of each game input in the kernel's input array, by name."""
GAME_INPUT = GameInputRows(*range(len(GAME_INPUT_FIELDS)))
"""Row indices of the game inputs by name (``GAME_INPUT.mu``), built from
``GAME_INPUT_FIELDS``, so a field added to the list cannot shift a row the kernel reads.
Numba reads the module-level tuple as a compile-time constant."""
_G = GAME_INPUT

GAME_OUTPUT_FIELDS = (
    "impact_parameter", "collision_efficiency",
    "field_ball_vx", "field_ball_vy", "field_ball_vz",
    "field_ball_wx", "field_ball_wy", "field_ball_wz",
    "field_bat_vx", "field_bat_vy", "field_bat_vz",
    "field_bat_wx", "field_bat_wy", "field_bat_wz",
)
"""Game outputs: the bat-frame impact parameter (``up * undercut``), the collision
efficiency ``q``, and the field-frame velocities (m/s) and spins (rad/s) of ball and bat
after the impact. (Before the impact they are functions of the inputs alone:
``mcbat.core.swing.frames.pitch_state`` and
``mcbat.core.swing.frames.swing_state``.)"""

FRAME_FIELDS = ("axial", "angle", *(f for f in INPUT_FIELDS if f.endswith("_in")), "e")
"""The bat-frame inputs the transform computes (the other ``INPUT_FIELDS`` are game
inputs of the same name, see ``bat_frame_columns``)."""

_NF = len(FRAME_FIELDS)
_NO = len(OUTPUT_FIELDS)
_NG = len(GAME_OUTPUT_FIELDS)
_COPIED = tuple(f for f in INPUT_FIELDS if f not in FRAME_FIELDS)
assert all(f in GAME_INPUT_FIELDS for f in _COPIED)


@njit
def _fail(col, code, frame, out, game_out, status, end_state):
    for r in range(_NF):
        frame[r, col] = math.nan
    for r in range(_NO):
        out[r, col] = math.nan
    out[_NO - 1, col] = 0.0  # rk4_steps
    for r in range(_NG):
        game_out[r, col] = math.nan
    status[col] = code
    end_state[col] = st.SLIDING


@njit(inline="always")
def _put3(arr, row, col, v):
    arr[row, col] = v[0]
    arr[row + 1, col] = v[1]
    arr[row + 2, col] = v[2]


@njit
def _contact(b, ball_radius, radius, slope, axial):
    """Azimuth, outward normal and contact point of a ball whose line passes ``b`` from
    the axis (``mcbat.core.geometry.angle_from_impact_parameter`` and
    ``mcbat.core.geometry.contact_frame``; ``sin(angle)`` is the ratio itself, which
    saves two transcendental calls per row). NaN angle when the ball misses."""
    ratio = b / ball_centre_radial_distance(ball_radius, radius, slope)
    if not abs(ratio) <= 1.0:
        nan3 = (math.nan, math.nan, math.nan)
        return math.nan, nan3, nan3
    c = math.sqrt(1.0 - ratio * ratio)
    inv = 1.0 / math.sqrt(1.0 + slope * slope)
    return math.asin(ratio), (c * inv, ratio * inv, -slope * inv), (radius * c, radius * ratio,
                                                                    axial)


@njit(inline="always")
def _situation(g, col):
    """The pitch, swing, bat and contact of row ``col`` of the game inputs."""
    return (Pitch(g[_G.pitch_speed, col], g[_G.pitch_vertical_approach_angle, col],
                  g[_G.pitch_horizontal_approach_angle, col], g[_G.pitch_spin_rate, col],
                  g[_G.pitch_spin_axis, col], g[_G.pitch_spin_efficiency, col],
                  g[_G.pitch_gyro_sign, col]),
            Swing(g[_G.handedness, col], g[_G.bat_speed, col], g[_G.attack_angle, col],
                  g[_G.attack_direction, col], g[_G.vertical_bat_angle, col],
                  g[_G.pivot, col]),
            BatBody(g[_G.bat_length, col], g[_G.bat_cm_from_knob, col]),
            GameContact(g[_G.from_barrel_end, col], g[_G.undercut, col]))


@njit
def incoming_state(game_inputs, col):
    """The pitch's velocity and spin and the bat's CM velocity and angular velocity
    before the impact, in the field frame (m/s, rad/s), of row ``col`` of the game inputs
    (NaN where the inputs are invalid)."""
    pitch, swing, bat, _ = _situation(game_inputs, col)
    _, pv, pw = pitch_state(pitch)
    _, _, v_cm, omega = swing_state(swing, bat)
    return pv, pw, v_cm, omega


#: ``solve_game_row``'s argument types as ``solve_game_batch`` passes them (C-contiguous
#: arrays, int64 row and step counts): the signature a kernel calling it by address
#: (``mcbat.core.jit.FunctionAddress``) is typed with, and the one the game kernel's
#: compile caches.
GAME_ROW_SIGNATURE = numba.types.none(
    numba.float64[:, ::1], numba.int64, numba.int64, numba.float64, numba.int64,
    numba.float64[:, ::1], numba.float64[:, ::1], numba.float64[:, ::1], numba.int8[::1],
    numba.int8[::1])


@njit
def solve_game_row(g, col, steps, tolerance, max_steps, frame, out, game_out, status,
                   end_state):
    """Solve row ``col`` of the game inputs ``g`` and write its outputs (see
    ``solve_game_batch``)."""
    ball_mass, ball_radius = g[_G.ball_mass, col], g[_G.ball_radius, col]
    ball_f = g[_G.ball_inertia_factor, col]
    radius, slope = g[_G.bat_radius, col], g[_G.bat_slope, col]
    pitch, swing, bat, contact = _situation(g, col)
    ok_p, pv, pw = pitch_state(pitch)
    ok_s, axis, v_cm, omega = swing_state(swing, bat)
    axial = (bat.length - bat.cm_from_knob) - contact.from_barrel_end
    if not (ok_p and ok_s and 0.0 <= contact.from_barrel_end <= bat.length):
        _fail(col, st.INVALID_INPUT, frame, out, game_out, status, end_state)
        return
    ok_f, i, j, k, up, rel = bat_frame(axis, v_cm, omega, pv, axial)
    b = up * contact.undercut
    angle, t3, r_c = _contact(b, ball_radius, radius, slope, axial)
    if not ok_f or math.isnan(angle):
        _fail(col, st.INVALID_INPUT, frame, out, game_out, status, end_state)
        return
    ball_v, ball_w = to_frame(i, j, k, pv), to_frame(i, j, k, pw)
    bat_v, bat_w = to_frame(i, j, k, v_cm), to_frame(i, j, k, omega)
    vn = dot(relative_contact_velocity(ball_radius, t3, r_c, ball_v, ball_w, bat_v, bat_w),
             t3)
    e = energetic_restitution(max(0.0, -vn), g[_G.e_ref, col], g[_G.e_slope, col],
                              g[_G.e_speed_ref, col], g[_G.e_location_factor, col])

    frame[0, col], frame[1, col] = axial, angle
    _put3(frame, 2, col, ball_v)
    _put3(frame, 5, col, ball_w)
    _put3(frame, 8, col, bat_v)
    _put3(frame, 11, col, bat_w)
    frame[14, col] = e

    r = solve_impact(ImpactInputs(
        ball_mass, ball_radius, ball_f, g[_G.bat_mass, col], g[_G.bat_transverse_inertia, col],
        g[_G.bat_axial_inertia, col], axial, angle, radius,
        slope, ball_v[0], ball_v[1], ball_v[2], ball_w[0], ball_w[1], ball_w[2],
        bat_v[0], bat_v[1], bat_v[2], bat_w[0], bat_w[1], bat_w[2], g[_G.mu, col], e,
        g[_G.e_x, col]),
        Accuracy(steps, tolerance, max_steps))
    store_impact(r, col, out, status, end_state)

    game_out[0, col] = b
    ball_v1 = from_frame(i, j, k, (r[2], r[3], r[4]))
    _put3(game_out, 2, col, ball_v1)
    _put3(game_out, 5, col, from_frame(i, j, k, (r[5], r[6], r[7])))
    _put3(game_out, 8, col, from_frame(i, j, k, (r[8], r[9], r[10])))
    _put3(game_out, 11, col, from_frame(i, j, k, (r[11], r[12], r[13])))
    # Collision efficiency along the line of the collision, n = the bat's velocity
    # relative to the ball (the point of the axis at the contact): exit speed
    # = q v_pitch + (1 + q) v_bat with both speeds taken along n.
    line = scale(-1.0 / norm(rel), rel)
    v_pitch = -dot(pv, line)
    v_bat = dot(pv, line) - dot(rel, line)
    game_out[1, col] = (norm(ball_v1) - v_bat) / (v_pitch + v_bat)


@njit(parallel=True)
def solve_game_batch(game_inputs, steps, tolerance, max_steps, frame, out, game_out,
                     status, end_state):
    """Solve ``game_inputs.shape[1]`` game situations in parallel.

    Parameters
    ----------
    game_inputs : float64[len(GAME_INPUT_FIELDS), n]
        One row per field of ``GAME_INPUT_FIELDS``.
    steps, tolerance, max_steps
        Accuracy settings of the impact kernel.
    frame : float64[len(FRAME_FIELDS), n]
        Written: the bat-frame inputs the transform computes (``FRAME_FIELDS``);
        ``bat_frame_columns`` completes the bat-frame case of every row.
    out : float64[len(OUTPUT_FIELDS), n]
        Written: the bat-frame outputs (``mcbat.core.batch.OUTPUT_FIELDS``).
    game_out : float64[len(GAME_OUTPUT_FIELDS), n]
        Written: ``GAME_OUTPUT_FIELDS``.
    status, end_state : int8[n]
        Written: codes from ``mcbat.core.status``.
    """
    n = game_inputs.shape[1]
    for col in numba.prange(n):
        # (np.int64: the parallel loop's index is typed int64, then uint64; each type
        # would compile solve_game_row again)
        solve_game_row(game_inputs, np.int64(col), steps, tolerance, max_steps, frame, out,
                       game_out, status, end_state)


def allocate_game_outputs(n):
    """Empty output arrays for ``solve_game_batch``:
    ``(frame, out, game_out, status, end_state)``."""
    return (np.empty((_NF, n)), np.empty((_NO, n)), np.empty((_NG, n)),
            np.empty(n, np.int8), np.empty(n, np.int8))


def bat_frame_columns(game_inputs, frame):
    """The bat-frame case of every row, as ``INPUT_FIELDS`` -> row views (no copies).

    Parameters
    ----------
    game_inputs : float64[len(GAME_INPUT_FIELDS), n]
    frame : float64[len(FRAME_FIELDS), n]
        As written by ``solve_game_batch``.
    """
    columns = {name: frame[i] for i, name in enumerate(FRAME_FIELDS)}
    columns.update({name: game_inputs[getattr(GAME_INPUT, name)] for name in _COPIED})
    return {name: columns[name] for name in INPUT_FIELDS}
