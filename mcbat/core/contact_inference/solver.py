"""The contact behind a measured batted ball: the game model run backwards.

Three observables of a ball in play (launch speed, launch angle, spray angle) against
three unknowns of the contact (the contact azimuth ``theta``, i.e. the undercut
``D = reach sin(theta)``; the bat speed or, when the bat speed is measured, the contact's
distance from the barrel end; the attack direction), solved by a damped Newton iteration
with a forward-difference Jacobian on the game kernel itself
(``mcbat.core.swing.game.solve_game_row``), one ball per ``prange`` iteration. The
equations, what is identified and what is assumed: ``README.md``.

Nothing raises inside the loop; every ball gets a status (``INFERENCE_STATUS_NAMES``)
and NaN outputs unless it converged.
"""

import math
from collections import namedtuple
from enum import IntEnum

import numba
import numpy as np

from mcbat.core import status as st
from mcbat.core.batch import OUTPUT_FIELDS
from mcbat.core.geometry import ball_centre_radial_distance, profile_surface
from mcbat.core.jit import njit
from mcbat.core.swing.frames import (
    SWEET_SPOT_FROM_BARREL_END,
    BatBody,
    Pitch,
    Swing,
    bat_frame,
    pitch_state,
    swing_state,
)
from mcbat.core.swing.game import (
    FRAME_FIELDS,
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
)

__all__ = ["CONVERGED", "INFERENCE_STATUS_NAMES", "INFER_BAT_SPEED", "INFER_FROM_BARREL_END",
           "INFER_NEAREST_BAT_SPEED", "INVALID_INPUT", "InferenceSettings", "InferenceStatus",
           "MAX_ITERATIONS", "NO_SOLUTION",
           "OBSERVED_FIELDS", "SOLUTION_FIELDS", "allocate_inference_outputs",
           "infer_contact_batch", "infer_contact_row"]


class InferenceStatus(IntEnum):
    """Status of an inferred contact (the kernel's status array; names in
    ``INFERENCE_STATUS_NAMES``). Python code compares with these members; the jitted
    kernels use the plain integer constants ``CONVERGED``, ``NO_SOLUTION``,
    ``MAX_ITERATIONS`` and ``INVALID_INPUT``, which hold the same values."""

    CONVERGED = 0
    NO_SOLUTION = 1
    MAX_ITERATIONS = 2
    INVALID_INPUT = 3


CONVERGED = int(InferenceStatus.CONVERGED)
"""The contact reproduces the observed ball to the tolerance."""
NO_SOLUTION = int(InferenceStatus.NO_SOLUTION)
"""No contact within the bounds reproduces the ball (e.g. a launch speed beyond what the
bat speed, or the contact position, can give; a launch angle beyond the reach)."""
MAX_ITERATIONS = int(InferenceStatus.MAX_ITERATIONS)
"""The iteration did not converge within ``max_iterations`` (no bound active)."""
INVALID_INPUT = int(InferenceStatus.INVALID_INPUT)
"""Non-finite or out-of-range numbers, or assumptions the game model refuses
(e.g. inconsistent swing angles): the forward model cannot be evaluated."""

INFERENCE_STATUS_NAMES = {CONVERGED: "converged", NO_SOLUTION: "no_solution",
                          MAX_ITERATIONS: "max_iterations", INVALID_INPUT: "invalid_input"}

INFER_BAT_SPEED = 0
"""Mode: the bat speed is unknown; the contact position is assumed (a game input)."""
INFER_FROM_BARREL_END = 1
"""Mode: the bat speed is measured (a game input); the contact position is unknown."""
INFER_NEAREST_BAT_SPEED = 2
"""Mode: the bat speed is measured with an error. The contact position is the unknown
first (as ``INFER_FROM_BARREL_END``); if no position along the bat gives the ball at
the measured bat speed, the bat speed nearest the measured one that does: the bat speed
is the unknown with the contact fixed where the launch speed per unit bat speed is
largest (a ball too fast) or smallest (too slow) along the bat. The caller judges the
adjustment against the measurement's error."""

OBSERVED_FIELDS = ("launch_speed", "launch_angle", "spray_angle")
"""The observables, SI: m/s, rad (elevation), rad (``atan2(v_x, v_y)``)."""

SOLUTION_FIELDS = ("undercut", "bat_speed", "from_barrel_end", "attack_direction",
                   "field_ball_vx", "field_ball_vy", "field_ball_vz",
                   "field_ball_wx", "field_ball_wy", "field_ball_wz",
                   "collision_efficiency")
"""Written per ball (SI): the contact (one of ``bat_speed``/``from_barrel_end`` is the
game input, the other inferred), the batted ball's field-frame velocity and spin, and
``q``."""

InferenceSettings = namedtuple("InferenceSettings", (
    "max_iterations", "tolerance", "steps", "impact_tolerance", "max_steps",
    "contact_side", "bat_speed_min", "bat_speed_max", "attack_direction_max",
    "from_barrel_end_min", "from_barrel_end_max", "contact_angle_max"))
"""Newton settings: at most ``max_iterations`` iterations, converged when every scaled
residual (launch speed relative, angles in rad) is ``<= tolerance``; the impact kernel's
accuracy (``steps``, ``impact_tolerance``, ``max_steps``); which root of the contact
position to take (``contact_side`` +1: the handle side of the launch speed's maximum,
-1: the barrel-end side); the bounds (m/s, rad, m, rad: ``|theta| <=
contact_angle_max``, ``D = reach sin(theta)``)."""

_G = {name: i for i, name in enumerate(GAME_INPUT_FIELDS)}
_NG = len(GAME_INPUT_FIELDS)
_NF = len(FRAME_FIELDS)
_NO = len(OUTPUT_FIELDS)
_NGO = len(GAME_OUTPUT_FIELDS)
_NS = len(SOLUTION_FIELDS)

_BALL_MASS, _BALL_RADIUS = _G["ball_mass"], _G["ball_radius"]
_BAT_MASS, _BAT_IT = _G["bat_mass"], _G["bat_transverse_inertia"]
_LENGTH, _CM_FROM_KNOB = _G["bat_length"], _G["bat_cm_from_knob"]
_RADIUS, _SLOPE = _G["bat_radius"], _G["bat_slope"]
_HANDED = _G["handedness"]
_PITCH_SPEED, _VAA, _HAA = (_G["pitch_speed"], _G["pitch_vertical_approach_angle"],
                            _G["pitch_horizontal_approach_angle"])
_BAT_SPEED, _ATTACK_ANGLE, _ATTACK_DIRECTION = (_G["bat_speed"], _G["attack_angle"],
                                                _G["attack_direction"])
_PITCH_SPIN, _PITCH_AXIS, _PITCH_EFF, _PITCH_GYRO = (
    _G["pitch_spin_rate"], _G["pitch_spin_axis"], _G["pitch_spin_efficiency"],
    _G["pitch_gyro_sign"])
_VBA = _G["vertical_bat_angle"]
_PIVOT, _FROM_BARREL_END, _UNDERCUT = _G["pivot"], _G["from_barrel_end"], _G["undercut"]
_E_REF, _E_SLOPE, _E_SPEED_REF, _E_LOCATION = (_G["e_ref"], _G["e_slope"], _G["e_speed_ref"],
                                               _G["e_location_factor"])
_FIELD_V = GAME_OUTPUT_FIELDS.index("field_ball_vx")
_FIELD_W = GAME_OUTPUT_FIELDS.index("field_ball_wx")
_Q = GAME_OUTPUT_FIELDS.index("collision_efficiency")

# Relative forward-difference steps of the Jacobian: the kernel's outputs move by ~1e-10
# (relative) when an input change shifts its adaptive steps, so the steps are 1e5 times
# that, and still small enough that the truncation error only slows Newton's last
# iteration from quadratic to a linear rate of ~1e-5.
_H_ANGLE = 1e-5          # rad, for theta and the attack direction
_H_SPEED = 1e-5          # relative, for the bat speed
_H_POSITION = 1e-5       # m, for the contact position
# Largest step per iteration (the model is far from linear over a whole bat).
_MAX_D_ANGLE = 0.35      # rad
_MAX_D_SPEED = 0.25      # relative
_MAX_D_POSITION = 0.02   # m
# The line search's fraction of the way to a bound; a move below _AT_BOUND of the
# range is none; an iterate within _NEAR_BOUND of the range from a bound when the
# iterations run out is pressed against it.
_TO_BOUND = 0.9
_AT_BOUND = 1e-12
_NEAR_BOUND = 1e-4
# A residual above this where the iteration stalls is a minimum that is not a root.
_STALL = 1e-6
# Grid of the launch-speed estimate along the bat (contact-position mode).
_GRID = 64
# The warm start's rough fits to the game kernel (R161, game preset; Newton corrects
# them): the ball's deflection from a square hit's direction per unit contact azimuth,
# the launch speed's fall with the azimuth, and a bat speed to start from.
_DEFLECTION_PER_THETA = 1.3
_OBLIQUE = 0.25
_BAT_SPEED_GUESS = 32.0
_MAX_TURN = 0.2  # rad
# A launch speed above the estimate's maximum along the bat is started this fraction of
# the way down from the maximum towards the barrel end's value.
_BELOW_PEAK = 0.1


@njit
def _location_factor(z, loc_z, loc_f):
    """The restitution table's factor at ``z`` (m from the barrel end): ``np.interp``'s
    value, written out for one point (the same operations in the same order, so the same
    bits; compiling numba's ``np.interp`` cost ~0.8 s of a first ``mcbat infer``). 1
    without a table."""
    n = loc_z.shape[0]
    if n == 0:
        return 1.0
    if n == 1 or z < loc_z[0]:
        return loc_f[0]
    if z != z:
        return z
    if z >= loc_z[n - 1]:
        return loc_f[n - 1]
    j = 0
    while z >= loc_z[j + 1]:
        j += 1
    if loc_z[j] == z:
        return loc_f[j]
    slope = (loc_f[j + 1] - loc_f[j]) / (loc_z[j + 1] - loc_z[j])
    value = slope * (z - loc_z[j]) + loc_f[j]
    if value != value:  # (np.interp's fallback for an infinite slope)
        value = slope * (z - loc_z[j + 1]) + loc_f[j + 1]
        if value != value and loc_f[j] == loc_f[j + 1]:
            value = loc_f[j]
    return value


@njit
def _surface(g, table, z):
    """Bat radius and slope at the contact ``z`` m from the barrel end (clipped onto the
    profile, as the API clips rounding in the conversion)."""
    axial = (g[_LENGTH, 0] - g[_CM_FROM_KNOB, 0]) - z
    lo, hi = table.breaks[0], table.breaks[table.breaks.shape[0] - 1]
    axial = min(max(axial, lo), hi)
    return profile_surface(table, axial)


@njit
def _evaluate(x, mode, g, table, loc_z, loc_f, settings, observed, scratch, r):
    """Run the game kernel at the unknowns ``x = (theta, speed or position, direction)``;
    write the scaled residual into ``r``. False if the kernel cannot solve it."""
    frame, out, game_out, status, end_state, game_row = scratch
    if mode == INFER_BAT_SPEED:
        g[_BAT_SPEED, 0] = x[1]
    else:
        g[_FROM_BARREL_END, 0] = x[1]
        g[_E_LOCATION, 0] = _location_factor(x[1], loc_z, loc_f)
    radius, slope = _surface(g, table, g[_FROM_BARREL_END, 0])
    g[_RADIUS, 0] = radius
    g[_SLOPE, 0] = slope
    g[_UNDERCUT, 0] = (ball_centre_radial_distance(g[_BALL_RADIUS, 0], radius, slope)
                       * math.sin(x[0]))
    g[_ATTACK_DIRECTION, 0] = x[2]
    # (np.int64(0): the argument types of GAME_ROW_SIGNATURE)
    game_row(g, np.int64(0), settings.steps, settings.impact_tolerance, settings.max_steps,
             frame, out, game_out, status, end_state)
    if status[0] != st.OK:
        return False
    vx, vy, vz = game_out[_FIELD_V, 0], game_out[_FIELD_V + 1, 0], game_out[_FIELD_V + 2, 0]
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    r[0] = (speed - observed[0]) / observed[0]
    r[1] = math.atan2(vz, math.hypot(vx, vy)) - observed[1]
    d = math.atan2(vx, vy) - observed[2]
    # the spray's difference on the circle (a ball can cross +-180 deg only far foul)
    if d > math.pi:
        d -= 2.0 * math.pi
    elif d < -math.pi:
        d += 2.0 * math.pi
    r[2] = d
    return math.isfinite(r[0]) and math.isfinite(r[1]) and math.isfinite(r[2])


@njit
def _head_on_speed(g, bat_speed, z, loc_z, loc_f):
    """Launch speed of a square, frictionless hit ``z`` m from the barrel end:
    ``q P + (1 + q) V`` with ``q = (e* - r)/(1 + r)``, ``r = m (1/M + d^2/I_t)`` and
    ``V`` the contact point's speed in the rotation about the pivot (README: the warm
    start)."""
    length, pivot = g[_LENGTH, 0], g[_PIVOT, 0]
    pitch = g[_PITCH_SPEED, 0]
    v = bat_speed * (length - z - pivot) / (length - SWEET_SPOT_FROM_BARREL_END - pivot)
    d = (length - g[_CM_FROM_KNOB, 0]) - z
    ratio = g[_BALL_MASS, 0] * (1.0 / g[_BAT_MASS, 0] + d * d / g[_BAT_IT, 0])
    e = g[_E_REF, 0] - g[_E_SLOPE, 0] * (pitch + v - g[_E_SPEED_REF, 0])
    e = min(max(e, 0.0), 1.0) * _location_factor(z, loc_z, loc_f)
    q = (e - ratio) / (1.0 + ratio)
    return q * pitch + (1.0 + q) * v


@njit
def _oblique(theta):
    """The warm start's fall of the launch speed with the contact azimuth (the normal
    part of the approach shrinks as ``cos(theta)``; a fit to the game kernel)."""
    c = math.cos(theta)
    return math.sqrt(c * c + _OBLIQUE * (1.0 - c * c))


@njit
def _collision_basis(g, bat_speed, direction, z):
    """The bat-frame directions of a square hit, in the field: ``i`` (the way a head-on
    ball leaves, away from the bat) and ``up`` (perpendicular to ``i`` and the bat axis,
    upwards), for a swing with the given speed and attack direction."""
    pitch = Pitch(g[_PITCH_SPEED, 0], g[_VAA, 0], g[_HAA, 0], g[_PITCH_SPIN, 0],
                  g[_PITCH_AXIS, 0], g[_PITCH_EFF, 0], g[_PITCH_GYRO, 0])
    swing = Swing(g[_HANDED, 0], bat_speed, g[_ATTACK_ANGLE, 0], direction,
                  g[_VBA, 0], g[_PIVOT, 0])
    ok_p, pv, _ = pitch_state(pitch)
    ok_s, axis, v_cm, omega = swing_state(swing, BatBody(g[_LENGTH, 0], g[_CM_FROM_KNOB, 0]))
    ok_f, i, j, _, up, _ = bat_frame(axis, v_cm, omega, pv,
                                     (g[_LENGTH, 0] - g[_CM_FROM_KNOB, 0]) - z)
    return ok_p and ok_s and ok_f, i, (up * j[0], up * j[1], up * j[2])


@njit
def _warm_start(mode, g, loc_z, loc_f, settings, observed, x, lower, upper):
    """Initial unknowns and their bounds (README: the warm start)."""
    hand = g[_HANDED, 0]
    pitch = g[_PITCH_SPEED, 0]
    theta_max = settings.contact_angle_max
    z0 = g[_FROM_BARREL_END, 0]
    v_guess = g[_BAT_SPEED, 0] if mode == INFER_FROM_BARREL_END else _BAT_SPEED_GUESS
    # the attack direction whose line of the collision points along the spray (batter's
    # frame), then corrected for the undercut's sideways part on a tilted bat
    s = hand * observed[2]
    ratio = math.sin(s) * pitch / (v_guess * math.cos(g[_ATTACK_ANGLE, 0]))
    direction = s + math.asin(min(max(ratio, -1.0), 1.0))
    cl = math.cos(observed[1])
    e = (cl * math.sin(observed[2]), cl * math.cos(observed[2]), math.sin(observed[1]))
    simple = direction
    theta = 0.0
    for _ in range(4):
        ok, i, up = _collision_basis(g, v_guess, direction, z0)
        if not ok:
            break
        delta = math.atan2(e[0] * up[0] + e[1] * up[1] + e[2] * up[2],
                           e[0] * i[0] + e[1] * i[1] + e[2] * i[2])
        cd, sd = math.cos(delta), math.sin(delta)
        target = (cd * e[0] - sd * up[0], cd * e[1] - sd * up[1])
        turn = math.atan2(target[0], target[1]) - math.atan2(i[0], i[1])
        # (the tilted bat's up turns with the attack direction too, so the full
        # correction can overshoot: each pass moves it at most _MAX_TURN)
        change = hand * turn * (1.0 + pitch / v_guess)
        direction += min(max(change, -_MAX_TURN), _MAX_TURN)
        theta = delta / _DEFLECTION_PER_THETA
    if not abs(direction) < 0.9 * settings.attack_direction_max:
        direction = simple
    theta = min(max(theta, -0.9 * theta_max), 0.9 * theta_max)
    target = observed[0] / _oblique(theta)
    lower[0], upper[0] = -theta_max, theta_max
    lower[2], upper[2] = -settings.attack_direction_max, settings.attack_direction_max
    x[0] = theta
    x[2] = min(max(direction, lower[2]), upper[2])
    if mode == INFER_BAT_SPEED:
        lower[1], upper[1] = settings.bat_speed_min, settings.bat_speed_max
        # launch speed is linear in the bat speed but for e*'s speed dependence: two
        # fixed-point passes
        v = v_guess
        for _ in range(2):
            ls1 = _head_on_speed(g, v, z0, loc_z, loc_f)
            ls0 = _head_on_speed(g, 0.0, z0, loc_z, loc_f)
            v = v * (target - ls0) / (ls1 - ls0) if ls1 != ls0 else v
        x[1] = min(max(v, lower[1]), upper[1])
        return
    # contact position: the launch speed's maximum along the bat splits it into two
    # branches; the chosen side's branch is bounded by the maximum
    z_lo, z_hi, z_peak, best = _along_bat(g, loc_z, loc_f, settings)
    v_s = g[_BAT_SPEED, 0]
    if settings.contact_side > 0:
        lower[1], upper[1] = z_peak, z_hi
    else:
        lower[1], upper[1] = z_lo, z_peak
    # the branch's crossing of the target, by bisection on the estimate; a target above
    # the estimate's maximum starts short of it (the Jacobian is singular there)
    target = min(target, best - _BELOW_PEAK * (best - _head_on_speed(g, v_s, z_lo, loc_z,
                                                                     loc_f)))
    a, b = lower[1], upper[1]
    fa = _head_on_speed(g, v_s, a, loc_z, loc_f) - target
    for _ in range(30):
        m = 0.5 * (a + b)
        fm = _head_on_speed(g, v_s, m, loc_z, loc_f) - target
        if (fm > 0.0) == (fa > 0.0):
            a, fa = m, fm
        else:
            b = m
    x[1] = 0.5 * (a + b)


@njit
def _along_bat(g, loc_z, loc_f, settings):
    """The contact positions' range ``(z_lo, z_hi)`` (m from the barrel end) and where the
    head-on estimate of the launch speed is largest along it, ``(z_peak, its value)``, at
    the bat speed in ``g``."""
    z_lo, z_hi = settings.from_barrel_end_min, settings.from_barrel_end_max
    z_hi = min(z_hi, g[_LENGTH, 0] - g[_PIVOT, 0] - 0.01)
    v_s = g[_BAT_SPEED, 0]
    best, z_peak = -math.inf, z_lo
    for k in range(_GRID + 1):
        z = z_lo + (z_hi - z_lo) * k / _GRID
        ls = _head_on_speed(g, v_s, z, loc_z, loc_f)
        if ls > best:
            best, z_peak = ls, z
    return z_lo, z_hi, z_peak, best


@njit
def _solve3(j, r, dx, scale):
    """``j dx = -r`` by Gaussian elimination with partial pivoting, the columns scaled by
    ``scale``. False if ``j`` is singular to working precision."""
    a = np.empty((3, 4))
    big = 0.0
    for i in range(3):
        for k in range(3):
            a[i, k] = j[i, k] * scale[k]
            big = max(big, abs(a[i, k]))
        a[i, 3] = -r[i]
    if not big > 0.0:
        return False
    for c in range(3):
        p = c
        for i in range(c + 1, 3):
            if abs(a[i, c]) > abs(a[p, c]):
                p = i
        if not abs(a[p, c]) > 1e-13 * big:
            return False
        if p != c:
            for k in range(4):
                a[c, k], a[p, k] = a[p, k], a[c, k]
        for i in range(c + 1, 3):
            f = a[i, c] / a[c, c]
            for k in range(c, 4):
                a[i, k] -= f * a[c, k]
    for c in range(2, -1, -1):
        s = a[c, 3]
        for k in range(c + 1, 3):
            s -= a[c, k] * dx[k]
        dx[c] = s / a[c, c]
    for c in range(3):
        dx[c] *= scale[c]
    return True


@njit
def _fail(col, code, solution, residual, status, iterations, evaluations, it, nev):
    for k in range(_NS):
        solution[k, col] = math.nan
    for k in range(3):
        residual[k, col] = math.nan
    status[col] = code
    iterations[col] = it
    evaluations[col] = nev


@njit
def _load(game_inputs, observed_all, mode, col, g, observed):
    """Copy ball ``col``'s inputs into ``g`` and ``observed``; False unless usable."""
    for k in range(3):
        observed[k] = observed_all[k, col]
    for k in range(_NG):
        g[k, 0] = game_inputs[k, col]
    # the unknowns' rows and what follows from them get finite placeholders (the warm
    # start and each evaluation set them); every other input must be finite
    g[_UNDERCUT, 0] = 0.0
    g[_ATTACK_DIRECTION, 0] = 0.0
    g[_RADIUS, 0] = 0.0
    g[_SLOPE, 0] = 0.0
    if mode == INFER_BAT_SPEED:
        g[_BAT_SPEED, 0] = 30.0
    elif mode == INFER_FROM_BARREL_END or mode == INFER_NEAREST_BAT_SPEED:
        g[_FROM_BARREL_END, 0] = 0.0
        g[_E_LOCATION, 0] = 1.0
    else:
        return False
    for k in range(_NG):
        if not math.isfinite(g[k, 0]):
            return False
    return (observed[0] > 0.0 and abs(observed[1]) < 0.5 * math.pi
            and abs(observed[2]) <= math.pi)


@njit
def _jacobian(x, r, mode, g, table, loc_z, loc_f, settings, observed, scratch, upper, jac,
              xt, rt):
    """Forward differences, each step away from the nearer (upper) bound. False if the
    kernel fails at a shifted point."""
    for k in range(3):
        if k == 1:
            h = _H_SPEED * x[1] if mode == INFER_BAT_SPEED else _H_POSITION
        else:
            h = _H_ANGLE
        if x[k] + h > upper[k]:
            h = -h
        for i in range(3):
            xt[i] = x[i]
        xt[k] = x[k] + h
        if not _evaluate(xt, mode, g, table, loc_z, loc_f, settings, observed, scratch, rt):
            return False
        for i in range(3):
            jac[i, k] = (rt[i] - r[i]) / h
    return True


@njit
def _step_limit(x, dx, mode):
    """The largest fraction of the Newton step within the model's nearly linear range."""
    limit = 1.0
    limit = min(limit, _MAX_D_ANGLE / max(abs(dx[0]), 1e-300))
    limit = min(limit, _MAX_D_ANGLE / max(abs(dx[2]), 1e-300))
    step1 = _MAX_D_SPEED * x[1] if mode == INFER_BAT_SPEED else _MAX_D_POSITION
    return min(limit, step1 / max(abs(dx[1]), 1e-300))


@njit
def _line_search(x, dx, merit, mode, g, table, loc_z, loc_f, settings, observed, scratch,
                 lower, upper, xt, rt):
    """Backtrack along the damped step projected on the bounds until the squared
    residual falls. Returns ``(accepted, moved, merit at xt, evaluations)``."""
    lam = _step_limit(x, dx, mode)
    # stop short of a bound (a tenth of the way left): at the launch speed's maximum
    # along the bat, the branches' common bound, the Jacobian is singular
    for i in range(3):
        if dx[i] > 0.0:
            lam = min(lam, _TO_BOUND * (upper[i] - x[i]) / dx[i])
        elif dx[i] < 0.0:
            lam = min(lam, _TO_BOUND * (lower[i] - x[i]) / dx[i])
    moved = False
    nev = 0
    for _ in range(8):
        for i in range(3):
            xt[i] = min(max(x[i] + lam * dx[i], lower[i]), upper[i])
            moved = moved or abs(xt[i] - x[i]) > _AT_BOUND * (upper[i] - lower[i])
        if not moved:
            break
        nev += 1
        if _evaluate(xt, mode, g, table, loc_z, loc_f, settings, observed, scratch, rt):
            mt = rt[0] * rt[0] + rt[1] * rt[1] + rt[2] * rt[2]
            if mt < merit * (1.0 - 1e-4 * lam) or mt == 0.0:
                return True, moved, mt, nev
        lam *= 0.5
    return False, moved, merit, nev


@njit
def _keep(scratch, g, best):
    """Save the batted ball and the undercut of the point just evaluated."""
    game_out = scratch[2]
    for k in range(3):
        best[k] = game_out[_FIELD_V + k, 0]
        best[3 + k] = game_out[_FIELD_W + k, 0]
    best[6] = game_out[_Q, 0]
    best[7] = g[_UNDERCUT, 0]


@njit
def _broyden(jac, x, xt, r, rt, col_scale):
    """Broyden's rank-one update of ``jac`` for the step ``xt - x`` (in the scaled
    unknowns, so that no unknown's unit dominates the step's norm)."""
    s = np.empty(3)
    size = 0.0
    for k in range(3):
        s[k] = (xt[k] - x[k]) / col_scale[k]
        size += s[k] * s[k]
    if not size > 0.0:
        return
    for i in range(3):
        predicted = 0.0
        for k in range(3):
            predicted += jac[i, k] * col_scale[k] * s[k]
        miss = (rt[i] - r[i]) - predicted
        for k in range(3):
            jac[i, k] += miss * s[k] / (size * col_scale[k])


@njit
def _newton(x, r, lower, upper, mode, g, table, loc_z, loc_f, settings, observed, scratch,
            best):
    """The damped Newton iteration from ``x`` (whose residual is ``r``). Returns
    ``(status, iterations, evaluations)``; ``x``, ``r``, ``best`` hold the last accepted
    point."""
    rt, jac = np.empty(3), np.empty((3, 3))
    xt, dx, col_scale = np.empty(3), np.empty(3), np.empty(3)
    col_scale[0], col_scale[2] = 1.0, 1.0
    col_scale[1] = 30.0 if mode == INFER_BAT_SPEED else 0.1
    merit = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    it, nev = 0, 0
    fresh = False  # whether jac is a finite-difference Jacobian at x (else Broyden's)
    while True:
        if max(abs(r[0]), abs(r[1]), abs(r[2])) <= settings.tolerance:
            return CONVERGED, it, nev
        if it >= settings.max_iterations:
            break
        it += 1
        if not fresh and it == 1:
            nev += 3
            if not _jacobian(x, r, mode, g, table, loc_z, loc_f, settings, observed,
                             scratch, upper, jac, xt, rt):
                return NO_SOLUTION, it, nev
            fresh = True
        if not _solve3(jac, r, dx, col_scale):
            accepted, moved = False, True
        else:
            accepted, moved, merit_t, n_ls = _line_search(x, dx, merit, mode, g, table,
                                                          loc_z, loc_f, settings, observed,
                                                          scratch, lower, upper, xt, rt)
            nev += n_ls
            # a Broyden step must at least halve the residual, or the Jacobian is redone
            accepted = accepted and (fresh or merit_t < 0.25 * merit)
        if not accepted:
            if not fresh:
                nev += 3
                if not _jacobian(x, r, mode, g, table, loc_z, loc_f, settings, observed,
                                 scratch, upper, jac, xt, rt):
                    return NO_SOLUTION, it, nev
                fresh = True
                continue
            # no decrease along the step: pressed against a bound, or at a minimum of
            # the residual that is not a root (no contact inside the bounds gives the
            # ball); or stalled at the kernel's own resolution just above the tolerance
            if not moved or max(abs(r[0]), abs(r[1]), abs(r[2])) > _STALL:
                return NO_SOLUTION, it, nev
            break
        _broyden(jac, x, xt, r, rt, col_scale)
        fresh = False
        for i in range(3):
            x[i] = xt[i]
            r[i] = rt[i]
        merit = merit_t
        _keep(scratch, g, best)
    for i in range(3):
        near = _NEAR_BOUND * (upper[i] - lower[i])
        if x[i] - lower[i] <= near or upper[i] - x[i] <= near:
            return NO_SOLUTION, it, nev
    return MAX_ITERATIONS, it, nev


@njit
def _nearest_bat_speed(g, table, loc_z, loc_f, settings, observed, scratch, x, lower, upper,
                       r, best):
    """The bat speed nearest the measured one (in ``g``) that gives the ball, with the
    contact fixed where the launch speed per unit bat speed is largest along the bat (the
    head-on estimate's peak: the least increase) or smallest (the range's end towards the
    handle: the least decrease). Returns ``(status, iterations, evaluations, bat speed,
    contact position)``; ``x``, ``r``, ``best`` hold the chosen solution."""
    measured = g[_BAT_SPEED, 0]
    # (np.int64: the row's compiled functions, not a second set for a constant mode)
    bat_speed_mode = np.int64(INFER_BAT_SPEED)
    _, z_hi, z_peak, _ = _along_bat(g, loc_z, loc_f, settings)
    xs, rs, bests = np.empty(3), np.empty(3), np.empty(8)
    found, chosen, it, nev = False, 0.0, 0, 0
    for k in range(2):
        z = z_peak if k == 0 else z_hi
        g[_BAT_SPEED, 0] = measured
        g[_FROM_BARREL_END, 0] = z
        g[_E_LOCATION, 0] = _location_factor(z, loc_z, loc_f)
        _warm_start(bat_speed_mode, g, loc_z, loc_f, settings, observed, xs, lower, upper)
        nev += 1
        if not _evaluate(xs, bat_speed_mode, g, table, loc_z, loc_f, settings, observed,
                         scratch, rs):
            continue
        _keep(scratch, g, bests)
        code, more_it, more_nev = _newton(xs, rs, lower, upper, bat_speed_mode, g, table,
                                          loc_z, loc_f, settings, observed, scratch, bests)
        it += more_it
        nev += more_nev
        if code != CONVERGED:
            continue
        if not found or abs(xs[1] - measured) < abs(x[1] - measured):
            found, chosen = True, z
            for i in range(3):
                x[i] = xs[i]
                r[i] = rs[i]
            for i in range(8):
                best[i] = bests[i]
    g[_BAT_SPEED, 0] = measured
    if not found:
        return NO_SOLUTION, it, nev, measured, math.nan
    return CONVERGED, it, nev, x[1], chosen


@njit
def infer_contact_row(game_inputs, observed_all, mode_all, col, table, loc_z, loc_f, settings,
                      game_row, solution, residual, status, iterations, evaluations):
    """Infer ball ``col`` (see ``infer_contact_batch``)."""
    mode = mode_all[col]
    nearest = mode == INFER_NEAREST_BAT_SPEED
    if nearest:
        mode = INFER_FROM_BARREL_END
    g, observed = np.empty((_NG, 1)), np.empty(3)
    # (np.int64: one compiled _fail for every call, not one per constant)
    none, one, invalid = np.int64(0), np.int64(1), np.int64(INVALID_INPUT)
    if not _load(game_inputs, observed_all, mode, col, g, observed):
        _fail(col, invalid, solution, residual, status, iterations, evaluations, none, none)
        return
    scratch = (np.empty((_NF, 1)), np.empty((_NO, 1)), np.empty((_NGO, 1)),
               np.empty(1, np.int8), np.empty(1, np.int8), game_row)
    x, lower, upper, r = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    best = np.empty(8)
    _warm_start(mode, g, loc_z, loc_f, settings, observed, x, lower, upper)
    if not _evaluate(x, mode, g, table, loc_z, loc_f, settings, observed, scratch, r):
        _fail(col, invalid, solution, residual, status, iterations, evaluations, none, one)
        return
    _keep(scratch, g, best)
    code, it, nev = _newton(x, r, lower, upper, mode, g, table, loc_z, loc_f, settings,
                            observed, scratch, best)
    nev += 1
    bat_speed = game_inputs[_BAT_SPEED, col]
    position = x[1] if mode == INFER_FROM_BARREL_END else game_inputs[_FROM_BARREL_END, col]
    if code != CONVERGED and nearest:
        code, more_it, more_nev, bat_speed, position = _nearest_bat_speed(
            g, table, loc_z, loc_f, settings, observed, scratch, x, lower, upper, r, best)
        it += more_it
        nev += more_nev
    elif mode == INFER_BAT_SPEED:
        bat_speed = x[1]
    if code != CONVERGED:
        _fail(col, code, solution, residual, status, iterations, evaluations, it, nev)
        for k in range(3):
            residual[k, col] = r[k]
        return
    solution[0, col] = best[7]
    solution[1, col] = bat_speed
    solution[2, col] = position
    solution[3, col] = x[2]
    for k in range(7):
        solution[4 + k, col] = best[k]
    for k in range(3):
        residual[k, col] = r[k]
    status[col] = CONVERGED
    iterations[col] = it
    evaluations[col] = nev


@njit(parallel=True)
def infer_contact_batch(game_inputs, observed, mode, table, loc_z, loc_f, settings, game_row,
                        solution, residual, status, iterations, evaluations):
    """Infer the contact of ``game_inputs.shape[1]`` batted balls in parallel.

    Parameters
    ----------
    game_inputs : float64[len(GAME_INPUT_FIELDS), n]
        The game inputs of each ball (``mcbat.core.swing.GAME_INPUT_FIELDS``): the
        measured pitch, the assumed swing and contact. The unknowns' rows are ignored
        (``undercut``, ``attack_direction``, ``bat_speed`` in bat-speed mode,
        ``from_barrel_end`` in position mode) and ``bat_radius``, ``bat_slope``,
        ``e_location_factor`` are recomputed from ``table`` and ``loc_z``, ``loc_f``.
    observed : float64[3, n]
        ``OBSERVED_FIELDS``, SI.
    mode : int8[n]
        ``INFER_BAT_SPEED``, ``INFER_FROM_BARREL_END`` or
        ``INFER_NEAREST_BAT_SPEED`` per ball.
    table : mcbat.core.geometry.ProfileTable
        The bat's surface (a cylinder is one interval of constant radius).
    loc_z, loc_f : float64[m]
        The restitution location table (m from the barrel end, factor); empty: none.
    settings : InferenceSettings
    game_row : first-class function of ``GAME_ROW_SIGNATURE``
        The game kernel's row function, ``mcbat.core.swing.game.solve_game_row``, by
        address (``mcbat.core.jit.FunctionAddress``): this kernel compiles without its
        call tree, which is compiled once, on its own.
    solution : float64[len(SOLUTION_FIELDS), n]
        Written: ``SOLUTION_FIELDS`` (NaN unless converged).
    residual : float64[3, n]
        Written: the final scaled residuals (launch speed relative, angles in rad).
    status : int8[n]
        Written: ``INFERENCE_STATUS_NAMES`` codes.
    iterations, evaluations : int32[n]
        Written: Newton iterations and game-kernel evaluations per ball.
    """
    n = game_inputs.shape[1]
    for col in numba.prange(n):
        # (np.int64: one compiled row function for the loop index's int64 and uint64)
        infer_contact_row(game_inputs, observed, mode, np.int64(col), table, loc_z, loc_f,
                          settings, game_row, solution, residual, status, iterations,
                          evaluations)


def allocate_inference_outputs(n):
    """Empty outputs of ``infer_contact_batch``:
    ``(solution, residual, status, iterations, evaluations)``."""
    return (np.empty((_NS, n)), np.empty((3, n)), np.empty(n, np.int8),
            np.empty(n, np.int32), np.empty(n, np.int32))
