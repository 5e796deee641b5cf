"""Slow, independent reference for the batted-ball flight: scipy ``solve_ivp`` (DOP853,
rtol 1e-10) with event location of the landing (the descending ball at ``z = h``, by
default the ground) and the apex (``v_z = 0``).

Written from the equations of ``mcbat/core/flight/README.md`` without the kernel's code.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp

from mcbat.core.units import RPM_PER_RAD_S

__all__ = ["reference_flight", "reference_height_at_distance"]



def _lift(model, s, lift, scale):
    if model == "constant":
        return lift
    if model == "nathan":
        return scale * (1.120 * s / (0.583 + 2.333 * s))
    return scale * (1.5 * s if s < 0.1 else 0.09 + 0.6 * s)


def _rhs(spin, density, mass, radius, model, decay_time, wind, drag, lift, gravity,
         drag_scale, lift_scale):
    w = np.asarray(spin, float)
    rate = float(np.linalg.norm(w))
    axis = w / rate if rate > 0 else np.zeros(3)
    c0 = density * math.pi * radius ** 2 / (2.0 * mass)
    wind = np.asarray(wind, float)

    def rhs(t, y):
        rel = y[3:] - wind
        speed = float(np.linalg.norm(rel))
        decay = 1.0 if decay_time is None else math.exp(-t * speed / (decay_time * 44.704))
        if model == "constant":
            cd = drag
        else:
            cd = 0.3008 * drag_scale + 0.0292 * rate * RPM_PER_RAD_S / 1000.0 * decay
        s = radius * rate * decay / speed if speed > 0 else 0.0
        cl = _lift(model, s, lift, lift_scale)
        acc = -c0 * cd * speed * rel + c0 * cl * speed * np.cross(axis, rel)
        acc[2] -= gravity
        return np.concatenate([y[3:], acc])

    return rhs


def reference_height_at_distance(start, velocity, spin, distance, *, density, mass, radius,
                                 decay_time=30.0, wind=(0.0, 0.0, 0.0), rtol=1e-10,
                                 drag_scale=1.0, lift_scale=1.0):
    """Height (m) and spray angle (rad) of Nathan's model's ball where its horizontal
    distance from home plate first reaches ``distance`` (m); None if it lands before."""
    rhs = _rhs(spin, density, mass, radius, "nathan", decay_time, wind, None, None, 9.80665,
               drag_scale, lift_scale)

    def reach(t, y):
        return math.hypot(y[0], y[1]) - distance

    def ground(t, y):
        return y[2]

    reach.terminal, reach.direction = True, 1.0
    ground.terminal, ground.direction = True, -1.0
    y0 = np.concatenate([np.asarray(start, float), np.asarray(velocity, float)])
    sol = solve_ivp(rhs, (0.0, 60.0), y0, method="DOP853", rtol=rtol, atol=1e-12,
                    events=(reach, ground))
    if not sol.t_events[0].size:
        return None
    at = sol.y_events[0][0]
    return float(at[2]), math.atan2(float(at[0]), float(at[1]))


def reference_flight(start, velocity, spin, *, density, mass, radius, model="nathan",
                     decay_time=30.0, wind=(0.0, 0.0, 0.0), drag=None, lift=None,
                     gravity=9.80665, rtol=1e-10, drag_scale=1.0, lift_scale=1.0,
                     landing_height=0.0):
    """Landing point, time and apex of one flight (SI, field frame).

    ``decay_time`` (s) or None for no spin decay; ``drag``/``lift`` for the constant
    model; ``drag_scale`` multiplies the spin-free drag 0.3008 and ``lift_scale`` the lift
    of the other models; the flight ends where the ball descends through
    ``landing_height`` (m). Returns a dict: ``hit_distance``, ``landing_x``, ``landing_y``,
    ``hang_time``, ``apex``; None if the ball reaches the ground without rising to the
    landing height.
    """
    rhs = _rhs(spin, density, mass, radius, model, decay_time, wind, drag, lift, gravity,
               drag_scale, lift_scale)

    def ground(t, y):
        return y[2]

    def landing(t, y):
        return y[2] - landing_height

    ground.terminal, ground.direction = True, -1.0
    landing.terminal, landing.direction = True, -1.0

    def top(t, y):
        return y[5]

    top.direction = -1.0
    y0 = np.concatenate([np.asarray(start, float), np.asarray(velocity, float)])
    sol = solve_ivp(rhs, (0.0, 60.0), y0, method="DOP853", rtol=rtol, atol=1e-12,
                    events=(landing, top, ground))
    if not sol.t_events[0].size:
        if sol.t_events[2].size:
            return None  # on the ground without rising to the landing height
        raise RuntimeError("the reference flight did not land within 60 s")
    land = sol.y_events[0][0]
    apex = max([y0[2]] + [float(e[2]) for e in sol.y_events[1]])
    return {"hit_distance": math.hypot(land[0], land[1]), "landing_x": float(land[0]),
            "landing_y": float(land[1]), "hang_time": float(sol.t_events[0][0]),
            "apex": apex}
