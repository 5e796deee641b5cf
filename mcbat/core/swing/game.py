"""The game kernel: pitch + swing + contact -> bat frame -> ``solve_impact`` -> field frame.

:func:`solve_game_batch` is a ``prange`` loop over struct-of-arrays, like
:func:`mcbat.core.batch.solve_batch`. Besides the field-frame results it writes the very
bat-frame case it solved (the rows of :data:`mcbat.core.batch.INPUT_FIELDS`), so every
row can be re-solved in the bat frame alone. Nothing raises inside the loop: a row whose
game inputs cannot be turned into an impact (inconsistent swing angles, an undercut
beyond the reach of ball and barrel, a contact off the bat) gets ``invalid_input``, a
pitch that does not approach the bat ``not_approaching``, with NaN outputs.
"""

import math

import numba
import numpy as np

from mcbat.core import status as st
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS
from mcbat.core.cabo2012.impact import solve_impact
from mcbat.core.geometry import angle_from_impact_parameter, contact_frame
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

__all__ = ["GAME_INPUT_FIELDS", "GAME_OUTPUT_FIELDS", "allocate_game_outputs",
           "solve_game_batch"]

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

GAME_OUTPUT_FIELDS = (
    "impact_parameter", "collision_efficiency",
    "field_ball_vx_in", "field_ball_vy_in", "field_ball_vz_in",
    "field_ball_wx_in", "field_ball_wy_in", "field_ball_wz_in",
    "field_bat_vx_in", "field_bat_vy_in", "field_bat_vz_in",
    "field_bat_wx_in", "field_bat_wy_in", "field_bat_wz_in",
    "field_ball_vx", "field_ball_vy", "field_ball_vz",
    "field_ball_wx", "field_ball_wy", "field_ball_wz",
    "field_bat_vx", "field_bat_vy", "field_bat_vz",
    "field_bat_wx", "field_bat_wy", "field_bat_wz",
)
"""Game outputs: the bat-frame impact parameter (``up * undercut``), the collision
efficiency ``q``, and the field-frame velocities (m/s) and spins (rad/s) of ball and bat
before (``_in``) and after the impact."""

_NB = len(INPUT_FIELDS)
_NO = len(OUTPUT_FIELDS)
_NG = len(GAME_OUTPUT_FIELDS)


@njit
def _fail(col, code, bat_in, out, game_out, status, end_state):
    for r in range(6, _NB):
        bat_in[r, col] = math.nan
    for r in range(_NO):
        out[r, col] = math.nan
    out[_NO - 1, col] = 0.0  # rk4_steps
    for r in range(_NG):
        game_out[r, col] = math.nan
    status[col] = code
    end_state[col] = st.SLIDING


@njit
def _put3(arr, row, col, v):
    arr[row, col] = v[0]
    arr[row + 1, col] = v[1]
    arr[row + 2, col] = v[2]


@njit
def solve_game_row(g, col, steps, tolerance, max_steps, bat_in, out, game_out, status,
                   end_state):
    """Solve row ``col`` of the game inputs ``g`` and write its outputs (see
    :func:`solve_game_batch`)."""
    ball_mass, ball_radius, ball_f = g[0, col], g[1, col], g[2, col]
    bat_mass, bat_it, bat_i3 = g[3, col], g[4, col], g[5, col]
    bat = BatBody(g[6, col], g[7, col])
    radius, slope = g[8, col], g[9, col]
    swing = Swing(g[10, col], g[18, col], g[19, col], g[20, col], g[21, col], g[22, col])
    pitch = Pitch(g[11, col], g[12, col], g[13, col], g[14, col], g[15, col], g[16, col],
                  g[17, col])
    contact = GameContact(g[23, col], g[24, col])
    mu, e_ref, e_slope, e_speed_ref, loc, e_x = (g[25, col], g[26, col], g[27, col],
                                                  g[28, col], g[29, col], g[30, col])
    for r, value in enumerate((ball_mass, ball_radius, ball_f, bat_mass, bat_it, bat_i3)):
        bat_in[r, col] = value

    ok_p, pv, pw = pitch_state(pitch)
    ok_s, axis, v_cm, omega = swing_state(swing, bat)
    axial = (bat.length - bat.cm_from_knob) - contact.from_barrel_end
    if not (ok_p and ok_s and 0.0 <= contact.from_barrel_end <= bat.length):
        _fail(col, st.INVALID_INPUT, bat_in, out, game_out, status, end_state)
        return
    ok_f, i, j, k, up, rel = bat_frame(axis, v_cm, omega, pv, axial)
    b = up * contact.undercut
    angle = angle_from_impact_parameter(b, ball_radius, radius, slope, 0.0)
    if not ok_f or math.isnan(angle):
        _fail(col, st.INVALID_INPUT, bat_in, out, game_out, status, end_state)
        return
    ball_v, ball_w = to_frame(i, j, k, pv), to_frame(i, j, k, pw)
    bat_v, bat_w = to_frame(i, j, k, v_cm), to_frame(i, j, k, omega)
    t1, t2, t3, r_c = contact_frame(axial, angle, radius, slope)
    vn = dot(relative_contact_velocity(ball_radius, t3, r_c, ball_v, ball_w, bat_v, bat_w),
             t3)
    e = energetic_restitution(max(0.0, -vn), e_ref, e_slope, e_speed_ref, loc)

    bat_in[6, col], bat_in[7, col], bat_in[8, col], bat_in[9, col] = axial, angle, radius, slope
    _put3(bat_in, 10, col, ball_v)
    _put3(bat_in, 13, col, ball_w)
    _put3(bat_in, 16, col, bat_v)
    _put3(bat_in, 19, col, bat_w)
    bat_in[22, col], bat_in[23, col], bat_in[24, col] = mu, e, e_x

    r = solve_impact(
        ball_mass, ball_radius, ball_f, bat_mass, bat_it, bat_i3, axial, angle, radius, slope,
        ball_v[0], ball_v[1], ball_v[2], ball_w[0], ball_w[1], ball_w[2],
        bat_v[0], bat_v[1], bat_v[2], bat_w[0], bat_w[1], bat_w[2], mu, e, e_x,
        steps, tolerance, max_steps)
    status[col] = r[0]
    end_state[col] = r[1]
    out[0, col] = r[2]
    out[1, col] = r[3]
    out[2, col] = r[4]
    out[3, col] = r[5]
    out[4, col] = r[6]
    out[5, col] = r[7]
    out[6, col] = r[8]
    out[7, col] = r[9]
    out[8, col] = r[10]
    out[9, col] = r[11]
    out[10, col] = r[12]
    out[11, col] = r[13]
    out[12, col] = r[14]
    out[13, col] = r[15]
    out[14, col] = r[16]
    out[15, col] = r[17]
    out[16, col] = r[18]
    out[17, col] = r[19]
    out[18, col] = r[20]
    out[19, col] = r[21]
    out[20, col] = r[22]
    out[21, col] = r[23]
    out[22, col] = r[24]
    out[23, col] = r[25]

    game_out[0, col] = b
    _put3(game_out, 2, col, pv)
    _put3(game_out, 5, col, pw)
    _put3(game_out, 8, col, v_cm)
    _put3(game_out, 11, col, omega)
    ball_v1 = from_frame(i, j, k, (r[2], r[3], r[4]))
    _put3(game_out, 14, col, ball_v1)
    _put3(game_out, 17, col, from_frame(i, j, k, (r[5], r[6], r[7])))
    _put3(game_out, 20, col, from_frame(i, j, k, (r[8], r[9], r[10])))
    _put3(game_out, 23, col, from_frame(i, j, k, (r[11], r[12], r[13])))
    # Collision efficiency along the line of the collision, n = the bat's velocity
    # relative to the ball (the point of the axis at the contact): exit speed
    # = q v_pitch + (1 + q) v_bat with both speeds taken along n.
    line = scale(-1.0 / norm(rel), rel)
    v_pitch = -dot(pv, line)
    v_bat = dot(pv, line) - dot(rel, line)
    game_out[1, col] = (norm(ball_v1) - v_bat) / (v_pitch + v_bat)


@njit(parallel=True)
def solve_game_batch(game_inputs, steps, tolerance, max_steps, bat_inputs, out, game_out,
                     status, end_state):
    """Solve ``game_inputs.shape[1]`` game situations in parallel.

    Parameters
    ----------
    game_inputs : float64[len(GAME_INPUT_FIELDS), n]
        One row per field of :data:`GAME_INPUT_FIELDS`.
    steps, tolerance, max_steps
        Accuracy settings of the impact kernel.
    bat_inputs : float64[len(INPUT_FIELDS), n]
        Written: the bat-frame case of every row (:data:`mcbat.core.batch.INPUT_FIELDS`).
    out : float64[len(OUTPUT_FIELDS), n]
        Written: the bat-frame outputs (:data:`mcbat.core.batch.OUTPUT_FIELDS`).
    game_out : float64[len(GAME_OUTPUT_FIELDS), n]
        Written: :data:`GAME_OUTPUT_FIELDS`.
    status, end_state : int8[n]
        Written: codes from :mod:`mcbat.core.status`.
    """
    n = game_inputs.shape[1]
    for col in numba.prange(n):
        solve_game_row(game_inputs, col, steps, tolerance, max_steps, bat_inputs, out,
                       game_out, status, end_state)


def allocate_game_outputs(n):
    """Empty output arrays for :func:`solve_game_batch`:
    ``(bat_inputs, out, game_out, status, end_state)``."""
    return (np.empty((_NB, n)), np.empty((_NO, n)), np.empty((_NG, n)),
            np.empty(n, np.int8), np.empty(n, np.int8))
