"""The batted ball's flight to the ground: an adaptive Dormand-Prince 5(4) integrator with
the landing and the apex located on the step's quintic Hermite interpolant, the
spreadsheet's fixed-step scheme for comparison, and the parallel batch kernel.

Field frame (Statcast): ``x`` towards first base, ``y`` towards the pitcher / centre
field, ``z`` up; SI units. The equations are in ``README.md``.
"""

import math
from collections import namedtuple
from enum import IntEnum

import numba
import numpy as np

from mcbat.core.flight.aero import Aero, coefficients
from mcbat.core.jit import njit

__all__ = ["DEFAULT_TOLERANCE", "FLIGHT_FIELDS", "GRAVITY", "MAX_STEPS", "SHEET_STEP",
           "Flight", "FlightParams", "FlightStatus", "allocate_flight_outputs", "fly", "fly_batch",
           "fly_batch_each", "fly_sheet", "height_at_distance", "height_at_distance_batch",
           "integrate", "pack_params", "rates"]

#: Standard gravity (m/s^2), the calculator's 32.174 ft/s^2.
GRAVITY = 9.80665
#: Default local error tolerance (relative to 10 m and 10 m/s per step; README.md).
DEFAULT_TOLERANCE = 1e-5
#: Most steps of one flight before it is reported as failed.
MAX_STEPS = 20000
#: The spreadsheet's time step (s).
SHEET_STEP = 0.01


class FlightStatus(IntEnum):
    """Status of a flight (``Flight.status``, ``fly_batch``'s status array).

    Python code compares with these members (an ``IntEnum`` member equals its integer,
    element-wise on arrays too); the jitted kernels use the plain integer constants
    ``OK``, ``INVALID``, ``MAX_STEPS_REACHED`` and ``NOT_RISEN``, which hold the same values.
    """

    OK = 0
    """The ball landed."""
    INVALID = 1
    """The launch point is below the ground, or an input is not finite."""
    MAX_STEPS_REACHED = 2
    """The integration hit its step limit before the ball landed."""
    NOT_RISEN = 3
    """The ball reached the ground without ever rising to the landing height."""


#: Status codes of a flight, as plain integers for the kernels (``FlightStatus``).
OK, INVALID = int(FlightStatus.OK), int(FlightStatus.INVALID)
MAX_STEPS_REACHED, NOT_RISEN = int(FlightStatus.MAX_STEPS_REACHED), int(FlightStatus.NOT_RISEN)

FLIGHT_FIELDS = ("hit_distance", "landing_x", "landing_y", "hang_time", "apex",
                 "flight_steps")
"""Outputs of ``fly_batch`` (m, m, m, s, m, 1): the horizontal distance of the landing
point from home plate, its coordinates, the time of flight, the greatest height, steps."""

FlightParams = namedtuple("FlightParams", ("drag_factor", "radius", "aero", "decay_rate",
                                           "gravity", "wind_x", "wind_y", "wind_z",
                                           "tolerance", "landing_height"))
"""Shared by every ball of a call: ``drag_factor`` ``c0 = rho A / (2 m)`` (1/m), the ball's
radius (m), the ``mcbat.core.flight.aero.Aero`` model, the spin decay rate
``1 / (tau 44.704 m/s)`` (s/m^2; 0: no decay), gravity (m/s^2), the wind (m/s), the
integrator's tolerance (0 selects the spreadsheet's scheme), and the landing height (m,
>= 0): the flight ends where the descending ball passes ``z = landing_height`` (0: the
ground; a catch height compares with a fielder's catch)."""

Flight = namedtuple("Flight", ("status", "distance", "landing_x", "landing_y", "hang_time",
                               "apex", "steps"))

_POS, _VEL = 10.0, 10.0  # error scales (m, m/s)


@njit(inline="always")
def rates(p, axis, spin, t, v):
    """Acceleration (m/s^2) at time ``t`` (s) and velocity ``v``; ``axis`` the unit spin
    axis (kept from the launch) and ``spin`` its initial rate (rad/s)."""
    rx, ry, rz = v[0] - p.wind_x, v[1] - p.wind_y, v[2] - p.wind_z
    speed = math.sqrt(rx * rx + ry * ry + rz * rz)
    decay = math.exp(-t * speed * p.decay_rate) if p.decay_rate > 0.0 else 1.0
    drag, lift = coefficients(p.aero, p.radius, spin, speed, decay)
    d = -p.drag_factor * drag * speed
    m = p.drag_factor * lift * speed
    return (d * rx + m * (axis[1] * rz - axis[2] * ry),
            d * ry + m * (axis[2] * rx - axis[0] * rz),
            d * rz + m * (axis[0] * ry - axis[1] * rx) - p.gravity)


@njit(inline="always")
def _hermite(s, h, y0, d0, a0, y1, d1, a1):
    """Quintic Hermite interpolant at ``s`` in [0, 1] of a step of length ``h`` with
    values, first and second derivatives at both ends; returns (value, d/dt, d2/dt2)."""
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    value = ((1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5) * y0
             + (s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5) * h * d0
             + 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5) * h * h * a0
             + (10.0 * s3 - 15.0 * s4 + 6.0 * s5) * y1
             + (-4.0 * s3 + 7.0 * s4 - 3.0 * s5) * h * d1
             + 0.5 * (s3 - 2.0 * s4 + s5) * h * h * a1)
    slope = ((-30.0 * s2 + 60.0 * s3 - 30.0 * s4) * y0
             + (1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4) * h * d0
             + 0.5 * (2.0 * s - 9.0 * s2 + 12.0 * s3 - 5.0 * s4) * h * h * a0
             + (30.0 * s2 - 60.0 * s3 + 30.0 * s4) * y1
             + (-12.0 * s2 + 28.0 * s3 - 15.0 * s4) * h * d1
             + 0.5 * (3.0 * s2 - 8.0 * s3 + 5.0 * s4) * h * h * a1) / h
    curve = ((-60.0 * s + 180.0 * s2 - 120.0 * s3) * y0
             + (-36.0 * s + 96.0 * s2 - 60.0 * s3) * h * d0
             + 0.5 * (2.0 - 18.0 * s + 36.0 * s2 - 20.0 * s3) * h * h * a0
             + (60.0 * s - 180.0 * s2 + 120.0 * s3) * y1
             + (-24.0 * s + 84.0 * s2 - 60.0 * s3) * h * d1
             + 0.5 * (6.0 * s - 24.0 * s2 + 20.0 * s3) * h * h * a1) / (h * h)
    return value, slope, curve


@njit
def _root(h, y0, d0, a0, y1, d1, a1, derivative, start=0.0):
    """``s`` in [start, 1] where the interpolant (``derivative`` False) or its slope (True)
    crosses zero, given a sign change between ``start`` and 1: safeguarded Newton."""
    lo, hi = start, 1.0
    f_lo = _hermite(start, h, y0, d0, a0, y1, d1, a1)[1 if derivative else 0]
    f_hi = _hermite(1.0, h, y0, d0, a0, y1, d1, a1)[1 if derivative else 0]
    s = start + (1.0 - start) * (f_lo / (f_lo - f_hi) if f_lo != f_hi else 0.5)
    for _ in range(60):
        value, slope, curve = _hermite(s, h, y0, d0, a0, y1, d1, a1)
        f, df = (slope, curve * h) if derivative else (value, slope * h)
        if (f > 0.0) == (f_lo > 0.0):
            lo = s
        else:
            hi = s
        step = f / df if df != 0.0 else 0.0
        s_new = s - step
        if not (lo < s_new < hi):
            s_new = 0.5 * (lo + hi)
        if abs(s_new - s) <= 1e-15 or hi - lo <= 1e-15:
            return s_new
        s = s_new
    return s


# Dormand-Prince 5(4) tableau (FSAL).
_C2, _C3, _C4, _C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
_A21 = 1.0 / 5.0
_A31, _A32 = 3.0 / 40.0, 9.0 / 40.0
_A41, _A42, _A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
_A51, _A52, _A53, _A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
_A61, _A62, _A63, _A64, _A65 = (9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0,
                                49.0 / 176.0, -5103.0 / 18656.0)
_B1, _B3, _B4, _B5, _B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
_E1, _E3, _E4, _E5, _E6, _E7 = (71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0,
                                -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0)


@njit(inline="always")
def _comb(y, h, c1, k1, c2, k2, c3, k3, c4, k4, c5, k5):
    return (y[0] + h * (c1 * k1[0] + c2 * k2[0] + c3 * k3[0] + c4 * k4[0] + c5 * k5[0]),
            y[1] + h * (c1 * k1[1] + c2 * k2[1] + c3 * k3[1] + c4 * k4[1] + c5 * k5[1]),
            y[2] + h * (c1 * k1[2] + c2 * k2[2] + c3 * k3[2] + c4 * k4[2] + c5 * k5[2]))


@njit
def _dp_step(p, axis, spin, t, x, v, a1, h):
    """One Dormand-Prince step: new position, velocity, acceleration (FSAL) and the error
    ratio (<= 1: within tolerance). The forces do not depend on the position, so the
    position's stage slopes are the stage velocities."""
    z3 = (0.0, 0.0, 0.0)
    v2 = _comb(v, h, _A21, a1, 0.0, z3, 0.0, z3, 0.0, z3, 0.0, z3)
    a2 = rates(p, axis, spin, t + _C2 * h, v2)
    v3 = _comb(v, h, _A31, a1, _A32, a2, 0.0, z3, 0.0, z3, 0.0, z3)
    a3 = rates(p, axis, spin, t + _C3 * h, v3)
    v4 = _comb(v, h, _A41, a1, _A42, a2, _A43, a3, 0.0, z3, 0.0, z3)
    a4 = rates(p, axis, spin, t + _C4 * h, v4)
    v5 = _comb(v, h, _A51, a1, _A52, a2, _A53, a3, _A54, a4, 0.0, z3)
    a5 = rates(p, axis, spin, t + _C5 * h, v5)
    v6 = _comb(v, h, _A61, a1, _A62, a2, _A63, a3, _A64, a4, _A65, a5)
    a6 = rates(p, axis, spin, t + h, v6)
    # positions: x' = v, so the stages' slopes are the stage velocities
    x_new = _comb(x, h, _B1, v, _B3, v3, _B4, v4, _B5, v5, _B6, v6)
    v_new = _comb(v, h, _B1, a1, _B3, a3, _B4, a4, _B5, a5, _B6, a6)
    a7 = rates(p, axis, spin, t + h, v_new)
    ratio = 0.0
    for i in range(3):
        ex = h * (_E1 * v[i] + _E3 * v3[i] + _E4 * v4[i] + _E5 * v5[i] + _E6 * v6[i]
                  + _E7 * v_new[i])
        ev = h * (_E1 * a1[i] + _E3 * a3[i] + _E4 * a4[i] + _E5 * a5[i] + _E6 * a6[i]
                  + _E7 * a7[i])
        ratio = max(ratio, abs(ex) / (p.tolerance * (_POS + abs(x_new[i]))),
                    abs(ev) / (p.tolerance * (_VEL + abs(v_new[i]))))
    return x_new, v_new, a7, ratio


@njit(inline="always")
def _launch(x, v, w):
    """Whether a launch can be flown (every component finite, not below the ground), and
    the spin's rate (rad/s) and axis (a unit vector; zeros without spin)."""
    spin = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    axis = (w[0] / spin, w[1] / spin, w[2] / spin) if spin > 0.0 else (0.0, 0.0, 0.0)
    ok = True
    for i in range(3):
        ok = ok and math.isfinite(x[i]) and math.isfinite(v[i]) and math.isfinite(w[i])
    return ok and x[2] >= 0.0, spin, axis


@njit(inline="always")
def _initial_state(p, axis, spin, t, v):
    """The integrator's state at the launch: the acceleration, the first step to try
    (s, by the tolerance) and the tries so far (none)."""
    return rates(p, axis, spin, t, v), 0.2 * (p.tolerance / 1e-7) ** 0.2, 0


@njit(inline="always")
def _accepted_step(p, axis, spin, t, x, v, a, h, steps, max_steps):
    """The next step within tolerance from ``(t, x, v, a)``: ``_dp_step`` with ``h``,
    shrunk after each rejected try, while ``steps`` (the tries so far) is under
    ``max_steps``. Returns ``(accepted, x1, v1, a1, ratio, h, steps)``: ``h`` the step
    taken, ``steps`` counting every try; ``accepted`` False once ``max_steps`` is spent."""
    while steps < max_steps:
        x1, v1, a1, ratio = _dp_step(p, axis, spin, t, x, v, a, h)
        steps += 1
        if ratio <= 1.0:
            return True, x1, v1, a1, ratio, h, steps
        h *= max(0.2, 0.9 * ratio ** -0.2) if math.isfinite(ratio) else 0.2
    return False, x, v, a, 0.0, h, steps


@njit(inline="always")
def _next_step(h, ratio):
    """The step to try after an accepted step ``h`` of error ratio ``ratio``."""
    return h * (min(5.0, 0.9 * ratio ** -0.2) if ratio > 0.0 else 5.0)


@njit
def _landing(h, t, x, v, a, x1, v1, a1, height, start):
    """Time, position where the step, from ``start`` (a fraction of it) on, descends
    through ``z = height``. The interpolant of ``z - height`` is that of ``z`` shifted: its
    end values move and its derivatives do not."""
    # (a constant flag: _root is compiled for each, without the other's branches; these
    # root searches are a good part of a five-step flight)
    s = _root(h, x[2] - height, v[2], a[2], x1[2] - height, v1[2], a1[2], False, start)
    lx = _hermite(s, h, x[0], v[0], a[0], x1[0], v1[0], a1[0])[0]
    ly = _hermite(s, h, x[1], v[1], a[1], x1[1], v1[1], a1[1])[0]
    return t + s * h, lx, ly


@njit
def _apex(h, x, v, a, x1, v1, a1):
    """Greatest height inside a step where the vertical velocity changes sign, and where
    in the step (a fraction of it) it lies."""
    s = _root(h, x[2], v[2], a[2], x1[2], v1[2], a1[2], True)
    return _hermite(s, h, x[2], v[2], a[2], x1[2], v1[2], a1[2])[0], s


@njit
def _record(samples, count, dt, t, h, x, v, a, x1, v1, a1, t_end):
    """Write the samples at multiples of ``dt`` in ``(t, min(t + h, t_end)]``."""
    while count < samples.shape[1] and count * dt <= t_end + 1e-12 * dt:
        ts = count * dt
        if ts > t + h:
            break
        s = (ts - t) / h
        samples[0, count] = ts
        for i in range(3):
            samples[1 + i, count] = _hermite(s, h, x[i], v[i], a[i], x1[i], v1[i], a1[i])[0]
        count += 1
    return count


@njit
def integrate(p, x, v, w, samples, dt=0.0, max_steps=MAX_STEPS):
    """``fly``, also writing the position every ``dt`` s (> 0) into ``samples``
    (``float64[4, m]``: t, x, y, z; up to the landing). Returns ``(Flight, count)``."""
    ok, spin, axis = _launch(x, v, w)
    if not ok:
        return Flight(INVALID, math.nan, math.nan, math.nan, math.nan, math.nan, 0), 0
    if p.tolerance == 0.0:
        return fly_sheet(p, axis, spin, x, v, max_steps), 0
    t, apex = 0.0, x[2]
    count = np.int64(0)  # (not a constant: one compiled _record)
    target = p.landing_height
    # The flight ends on a downward crossing of the landing height; a ball launched below
    # it must first rise above it (a catch height above the launch point).
    risen = x[2] >= target
    if x[2] == target and v[2] <= 0.0:
        if dt > 0.0 and samples.shape[1] > 0:
            samples[0, 0], samples[1, 0], samples[2, 0], samples[3, 0] = 0.0, x[0], x[1], x[2]
            count = 1
        return Flight(OK, math.hypot(x[0], x[1]), x[0], x[1], 0.0, apex, 0), count
    a, h, steps = _initial_state(p, axis, spin, t, v)
    while True:
        accepted, x1, v1, a1, ratio, h, steps = _accepted_step(p, axis, spin, t, x, v, a, h,
                                                               steps, max_steps)
        if not accepted:
            break
        start = 0.0
        if v[2] > 0.0 and v1[2] <= 0.0:
            top, s_top = _apex(h, x, v, a, x1, v1, a1)
            apex = max(apex, top)
            if not risen and top >= target:  # rose above the landing height in this step
                risen, start = True, s_top
        if x1[2] < target and risen:
            t_land, lx, ly = _landing(h, t, x, v, a, x1, v1, a1, target, start)
            if dt > 0.0:
                count = _record(samples, count, dt, t, h, x, v, a, x1, v1, a1, t_land)
            return Flight(OK, math.hypot(lx, ly), lx, ly, t_land, apex, steps), count
        if x1[2] < 0.0:  # on the ground without reaching the landing height
            return (Flight(NOT_RISEN, math.nan, math.nan, math.nan, math.nan, apex, steps),
                    count)
        risen = risen or x1[2] >= target
        if dt > 0.0:
            count = _record(samples, count, dt, t, h, x, v, a, x1, v1, a1, t + h)
        t += h
        x, v, a = x1, v1, a1
        h = _next_step(h, ratio)
    return (Flight(MAX_STEPS_REACHED, math.nan, math.nan, math.nan, math.nan, math.nan, steps),
            count)


@njit
def fly(p, x, v, w, max_steps=MAX_STEPS):
    """One flight from position ``x`` (m) with velocity ``v`` (m/s) and spin ``w`` (rad/s,
    field frame) to the ground (``z = 0``); returns a ``Flight`` (SI). The spin axis
    keeps its launch direction; its rate decays as the model says (``README.md``)."""
    # (np.int64: the integrate the API compiles, which passes MAX_STEPS, not one for the
    # constant default)
    return integrate(p, x, v, w, np.empty((4, 0)), 0.0, np.int64(max_steps))[0]


@njit
def fly_sheet(p, axis, spin, x, v, max_steps=MAX_STEPS):
    """The spreadsheet's scheme: ``x += v dt + a dt^2 / 2``, ``v += a dt`` with
    ``dt`` = ``SHEET_STEP``; the landing is its last point above the ground, as the
    sheet reports it (this reproduces its published 400.5 ft)."""
    dt = SHEET_STEP
    t, apex = 0.0, x[2]
    target = p.landing_height
    risen = x[2] >= target
    for steps in range(1, max_steps + 1):
        a = rates(p, axis, spin, t, v)
        x1 = (x[0] + v[0] * dt + 0.5 * a[0] * dt * dt, x[1] + v[1] * dt + 0.5 * a[1] * dt * dt,
              x[2] + v[2] * dt + 0.5 * a[2] * dt * dt)
        v = (v[0] + a[0] * dt, v[1] + a[1] * dt, v[2] + a[2] * dt)
        apex = max(apex, x1[2])
        if x1[2] < target and risen:  # the sheet reports its last point above the ground
            return Flight(OK, math.hypot(x[0], x[1]), x[0], x[1], t, apex, steps)
        if x1[2] < 0.0:
            return Flight(NOT_RISEN, math.nan, math.nan, math.nan, math.nan, apex, steps)
        risen = risen or x1[2] >= target
        x = x1
        t += dt
    return Flight(MAX_STEPS_REACHED, math.nan, math.nan, math.nan, math.nan, math.nan,
                  max_steps)


def pack_params(p):
    """``FlightParams`` as the flat float64 array ``fly_batch`` takes (numba's
    parallel loops do not accept named tuples of mixed types as arguments)."""
    return np.array([p.drag_factor, p.radius, p.aero.model, p.aero.drag, p.aero.lift,
                     p.aero.drag_scale, p.aero.lift_scale, p.decay_rate, p.gravity, p.wind_x,
                     p.wind_y, p.wind_z, p.tolerance, p.landing_height], np.float64)


@njit(inline="always")
def _unpack(s):
    return FlightParams(s[0], s[1], Aero(int(s[2]), s[3], s[4], s[5], s[6]), s[7], s[8], s[9],
                        s[10], s[11], s[12], s[13])


@njit(parallel=True)
def fly_batch(params, start, velocity, spin, out, status):
    """Fly ``start.shape[1]`` balls in parallel.

    Parameters
    ----------
    params : float64[14]
        ``pack_params`` of the ``FlightParams`` shared by every ball.
    start, velocity, spin : float64[3, n]
        Field frame: position (m), velocity (m/s), spin (rad/s).
    out : float64[len(FLIGHT_FIELDS), n]
        Written: ``FLIGHT_FIELDS``.
    status : int8[n]
        Written: 0 ok, 1 invalid input (non-finite, below the ground), 2 too many steps,
        3 the ball reached the ground without rising to the landing height.
    """
    for i in numba.prange(start.shape[1]):
        p = _unpack(params)  # inside the loop: parallel regions take no named tuples
        f = fly(p, (start[0, i], start[1, i], start[2, i]),
                (velocity[0, i], velocity[1, i], velocity[2, i]),
                (spin[0, i], spin[1, i], spin[2, i]))
        _store(f, i, out, status)


@njit(inline="always")
def _store(f, i, out, status):
    """Write flight ``f`` into column ``i`` of the batch outputs."""
    status[i] = f.status
    out[0, i] = f.distance
    out[1, i] = f.landing_x
    out[2, i] = f.landing_y
    out[3, i] = f.hang_time
    out[4, i] = f.apex
    out[5, i] = f.steps


def allocate_flight_outputs(n):
    """``(out, status)`` for ``fly_batch``."""
    return np.empty((len(FLIGHT_FIELDS), n)), np.empty(n, np.int8)


@njit(parallel=True)
def fly_batch_each(params, start, velocity, spin, out, status):
    """``fly_batch`` with every ball's own parameters: ``params`` is
    ``float64[14, n]``, column ``i`` the ``pack_params`` of ball ``i`` (its own air
    density, wind, drag and lift scales, landing height)."""
    for i in numba.prange(start.shape[1]):
        p = _unpack(params[:, i])
        f = fly(p, (start[0, i], start[1, i], start[2, i]),
                (velocity[0, i], velocity[1, i], velocity[2, i]),
                (spin[0, i], spin[1, i], spin[2, i]))
        _store(f, i, out, status)


@njit
def _radius_crossing(h, x, v, a, x1, v1, a1, distance):
    """Fraction ``s`` of a step where the horizontal distance from home plate rises
    through ``distance`` (bisection on the step's interpolant; the distance grows
    monotonically inside a step of a batted ball)."""
    lo, hi = 0.0, 1.0
    for _ in range(60):
        s = 0.5 * (lo + hi)
        px = _hermite(s, h, x[0], v[0], a[0], x1[0], v1[0], a1[0])[0]
        py = _hermite(s, h, x[1], v[1], a[1], x1[1], v1[1], a1[1])[0]
        if px * px + py * py < distance * distance:
            lo = s
        else:
            hi = s
        if hi - lo <= 1e-13:
            break
    return 0.5 * (lo + hi)


@njit
def height_at_distance(p, x, v, w, distance, max_steps=MAX_STEPS):
    """Height (m) and spray angle (rad, ``atan2(x, y)``) of the ball where its horizontal
    distance from home plate first reaches ``distance`` (m): where it meets a fence
    standing there. NaN, NaN when it comes down (``z = 0``) before; the flight's
    parameters as ``fly`` (the landing height is not used)."""
    ok, spin, axis = _launch(x, v, w)
    if not (ok and math.isfinite(distance) and distance > 0.0) or p.tolerance == 0.0:
        return math.nan, math.nan
    if x[0] * x[0] + x[1] * x[1] >= distance * distance:
        return x[2], math.atan2(x[0], x[1])
    t = 0.0
    a, h, steps = _initial_state(p, axis, spin, t, v)
    while True:
        accepted, x1, v1, a1, ratio, h, steps = _accepted_step(p, axis, spin, t, x, v, a, h,
                                                               steps, max_steps)
        if not accepted:
            return math.nan, math.nan
        if x1[0] * x1[0] + x1[1] * x1[1] >= distance * distance:
            s = _radius_crossing(h, x, v, a, x1, v1, a1, distance)
            z = _hermite(s, h, x[2], v[2], a[2], x1[2], v1[2], a1[2])[0]
            px = _hermite(s, h, x[0], v[0], a[0], x1[0], v1[0], a1[0])[0]
            py = _hermite(s, h, x[1], v[1], a[1], x1[1], v1[1], a1[1])[0]
            if z < 0.0:
                return math.nan, math.nan
            return z, math.atan2(px, py)
        if x1[2] < 0.0:
            return math.nan, math.nan
        t += h
        x, v, a = x1, v1, a1
        h = _next_step(h, ratio)


@njit(parallel=True)
def height_at_distance_batch(params, start, velocity, spin, distance, out):
    """``height_at_distance`` of ``start.shape[1]`` balls, each with its own
    parameters (``float64[14, n]`` as ``fly_batch_each``) and distance (m);
    ``out`` (``float64[2, n]``) receives the height (m) and the spray angle (rad)."""
    for i in numba.prange(start.shape[1]):
        p = _unpack(params[:, i])
        z, phi = height_at_distance(p, (start[0, i], start[1, i], start[2, i]),
                                    (velocity[0, i], velocity[1, i], velocity[2, i]),
                                    (spin[0, i], spin[1, i], spin[2, i]), distance[i])
        out[0, i] = z
        out[1, i] = phi
