"""The history of one impact along the normal impulse ``I``, for plots and diagnostics.

:func:`contact_history` evaluates the relative contact velocity and the works at given
impulses, following the same phases as :func:`mcbat.core.cabo2012.contact.solve_contact`
(RK4 slip with the same step rule, then the stick or re-slip closed form). It does not stop
at separation: the curves continue past ``I_f`` so that plots can show where the
separation rules cut them.
"""

import math

import numpy as np

from mcbat.core.cabo2012.contact import (
    DEFAULT_TOLERANCE,
    MAX_SLIP_FRACTION,
    STICK_TOLERANCE,
    inverse_slip_stiffness,
    reslip_direction,
    rk4_step,
    slip_velocity,
    stick_impulse_rate,
)
from mcbat.core.jit import njit

__all__ = ["MAX_HISTORY_STEPS", "RESLIP", "SLIP", "STICK", "contact_history"]

SLIP = 0
STICK = 1
RESLIP = 2
MAX_HISTORY_STEPS = 1_000_000


@njit
def contact_history(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, impulses,
                    tolerance=DEFAULT_TOLERANCE):
    """Relative contact velocity and works at the impulses ``impulses`` (sorted, >= 0).

    Returns
    -------
    out : float64[n, 6]
        Columns ``v1, v2, v_n`` (m/s), ``W_n``, ``W_fr`` (J) and the phase
        (0 slip, 1 stick, 2 re-slip) at each impulse.
    stick_impulse : float
        ``I_s`` (NaN if slip does not stop before the last impulse requested).
    """
    n = impulses.shape[0]
    out = np.full((n, 6), np.nan)
    v_scale = math.sqrt(v01 * v01 + v02 * v02 + v0n * v0n)
    s_stop = STICK_TOLERANCE * v_scale
    i_scale = 2.0 * abs(v0n) / k33
    # Fine steps, also relative to the span plotted: the curves are evaluated inside steps
    # by partial RK4 steps, which must not span a large part of the plot.
    h_max = i_scale / 256.0
    if n and impulses[n - 1] > 0.0:
        h_max = min(h_max, impulses[n - 1] / 512.0)
    imp = 0.0
    p1 = 0.0
    p2 = 0.0
    wn = 0.0
    wfr = 0.0
    i_s = math.nan
    j = 0
    phase = SLIP
    inv_mu_ktt = inverse_slip_stiffness(k11, k12, k22, mu)
    # ---- slip, recorded at the requested impulses by partial steps ----
    passes = 0
    while j < n and mu > 0.0:
        passes += 1
        if passes > MAX_HISTORY_STEPS:
            break  # bounded: the remaining points stay NaN
        v1, v2, vn = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp)
        s = math.sqrt(v1 * v1 + v2 * v2)
        if s <= s_stop:
            break
        u1 = v1 / s
        u2 = v2 / s
        g1 = k13 - mu * (k11 * u1 + k12 * u2)
        g2 = k23 - mu * (k12 * u1 + k22 * u2)
        sigma = u1 * g1 + u2 * g2
        h = h_max
        if sigma < 0.0:
            dist = s / (-sigma)
            if dist <= 1e-9 * i_scale:
                # Land: v_t falls linearly to zero over the last sliver of slip.
                while j < n and impulses[j] <= imp + dist:
                    d = impulses[j] - imp
                    out[j, 0] = v1 + g1 * d
                    out[j, 1] = v2 + g2 * d
                    out[j, 2] = vn + (k33 - mu * (k13 * u1 + k23 * u2)) * d
                    out[j, 3] = wn + d * (vn + 0.5 * (k33 - mu * (k13 * u1 + k23 * u2)) * d)
                    out[j, 4] = wfr - mu * d * (s - 0.5 * (-sigma) * d)
                    out[j, 5] = SLIP
                    j += 1
                dvn = k33 - mu * (k13 * u1 + k23 * u2)
                wn += dist * (vn + 0.5 * dvn * dist)
                wfr -= 0.5 * mu * s * dist
                p1 -= mu * u1 * dist
                p2 -= mu * u2 * dist
                imp += dist
                break
            h = min(h, MAX_SLIP_FRACTION * dist)
        h = min(h, MAX_SLIP_FRACTION * s * inv_mu_ktt)  # RK4 stability, as in the solver
        a = (-mu * u1, -mu * u2, vn, -mu * s)
        while j < n and impulses[j] <= imp + h:
            d = impulses[j] - imp
            q = rk4_step(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, imp, p1, p2, wn,
                          wfr, d, a[0], a[1], a[2], a[3])
            w1, w2, wv = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, q[1], q[2],
                                   q[0])
            out[j, 0] = w1
            out[j, 1] = w2
            out[j, 2] = wv
            out[j, 3] = q[3]
            out[j, 4] = q[4]
            out[j, 5] = SLIP
            j += 1
        imp, p1, p2, wn, wfr = rk4_step(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                                         imp, p1, p2, wn, wfr, h, a[0], a[1], a[2], a[3])
    if j >= n or passes > MAX_HISTORY_STEPS:
        return out, i_s
    # ---- slip has stopped: stick or re-slip, linear in I ----
    if mu > 0.0:
        i_s = imp
        f1, f2 = stick_impulse_rate(k11, k12, k13, k22, k23)
        if f1 * f1 + f2 * f2 <= mu * mu:
            d1, d2, phase = f1, f2, STICK
        else:
            u1, u2, lam = reslip_direction(k11, k12, k13, k22, k23, mu)
            d1, d2, phase = -mu * u1, -mu * u2, RESLIP
    else:
        d1, d2 = 0.0, 0.0
    v1, v2, vn = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp)
    c1 = k11 * d1 + k12 * d2 + k13
    c2 = k12 * d1 + k22 * d2 + k23
    slope = k13 * d1 + k23 * d2 + k33
    while j < n:
        d = impulses[j] - imp
        out[j, 0] = v1 + c1 * d
        out[j, 1] = v2 + c2 * d
        out[j, 2] = vn + slope * d
        out[j, 3] = wn + d * (vn + 0.5 * slope * d)
        out[j, 4] = wfr + d * (v1 * d1 + v2 * d2) + 0.5 * d * d * (c1 * d1 + c2 * d2)
        out[j, 5] = phase
        j += 1
    return out, i_s
