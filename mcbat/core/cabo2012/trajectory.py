"""The history of one impact along the normal impulse ``I``, for plots and diagnostics.

:func:`contact_history` evaluates the relative contact velocity and the works at given
impulses, following the same phases as :func:`mcbat.core.cabo2012.contact.solve_contact`
(RK4 slip with the same step rule, :func:`~mcbat.core.cabo2012.contact.slip_step_size`,
on a finer step cap; then the stick or re-slip closed form). It does not stop
at separation: the curves continue past ``I_f`` so that plots can show where the
separation rules cut them.
"""

import math

import numpy as np

from mcbat.core import status as st
from mcbat.core.cabo2012.contact import (
    DEFAULT_TOLERANCE,
    STICK_TOLERANCE,
    Contact,
    SlipState,
    after_slip,
    inverse_slip_stiffness,
    remove_residual_slip,
    rk4_step,
    slip_point,
    slip_step_size,
    velocity,
)
from mcbat.core.jit import njit

__all__ = ["MAX_HISTORY_STEPS", "RESLIP", "SLIP", "STICK", "contact_history"]

SLIP = 0
STICK = 1
RESLIP = 2
MAX_HISTORY_STEPS = 1_000_000


@njit(inline="always")
def _record(out, j, c, state, phase):
    v1, v2, vn = velocity(c, state.p1, state.p2, state.imp)
    out[j, 0] = v1
    out[j, 1] = v2
    out[j, 2] = vn
    out[j, 3] = state.wn
    out[j, 4] = state.wfr
    out[j, 5] = phase


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
    c = Contact(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu)
    n = impulses.shape[0]
    out = np.full((n, 6), np.nan)
    s_stop = STICK_TOLERANCE * math.sqrt(v01 * v01 + v02 * v02 + v0n * v0n)
    i_scale = 2.0 * abs(v0n) / k33
    budget = tolerance * i_scale
    # Fine steps, also relative to the span plotted: the curves are evaluated inside steps
    # by partial steps, which must not span a large part of the plot.
    h_max = i_scale / 256.0
    if n and impulses[n - 1] > 0.0:
        h_max = min(h_max, impulses[n - 1] / 512.0)
    state = SlipState(0.0, 0.0, 0.0, 0.0, 0.0)
    i_s = math.nan
    j = 0
    inv_mu_ktt = inverse_slip_stiffness(k11, k12, k22, mu)
    # ---- slip, recorded at the requested impulses by partial steps ----
    passes = 0
    while j < n and mu > 0.0:
        passes += 1
        if passes > MAX_HISTORY_STEPS:
            return out, i_s  # bounded: the remaining points stay NaN
        pt = slip_point(c, state)
        if pt.s <= s_stop:
            break
        h, land = slip_step_size(c, pt, h_max, budget, budget, inv_mu_ktt, s_stop)
        rates = (-mu * pt.u1, -mu * pt.u2, pt.vn, -mu * pt.s)
        while j < n and impulses[j] <= state.imp + h:
            d = impulses[j] - state.imp
            if land:  # v_t falls linearly to zero over the last sliver of slip
                part = SlipState(state.imp + d, state.p1 - mu * pt.u1 * d,
                                 state.p2 - mu * pt.u2 * d,
                                 state.wn + d * (pt.vn + 0.5 * pt.dvn * d),
                                 state.wfr - mu * d * (pt.s - 0.5 * (-pt.sigma) * d))
            else:
                part = rk4_step(c, state, d, rates)
            _record(out, j, c, part, SLIP)
            j += 1
        if land:
            state = SlipState(state.imp + h, state.p1 - mu * pt.u1 * h,
                              state.p2 - mu * pt.u2 * h,
                              state.wn + h * (pt.vn + 0.5 * pt.dvn * h),
                              state.wfr - 0.5 * mu * pt.s * h)
            state = remove_residual_slip(c, state)  # as the solver does
            break
        state = rk4_step(c, state, h, rates)
    if j >= n:
        return out, i_s
    # ---- slip has stopped: stick or re-slip, linear in I ----
    phase = SLIP
    if mu > 0.0:
        i_s = state.imp
    _, end_state, d1, d2 = after_slip(c)
    if mu > 0.0:
        phase = STICK if end_state == st.STUCK else RESLIP
    v1, v2, vn = velocity(c, state.p1, state.p2, state.imp)
    c1 = k11 * d1 + k12 * d2 + k13
    c2 = k12 * d1 + k22 * d2 + k23
    slope = k13 * d1 + k23 * d2 + k33
    while j < n:
        d = impulses[j] - state.imp
        out[j, 0] = v1 + c1 * d
        out[j, 1] = v2 + c2 * d
        out[j, 2] = vn + slope * d
        out[j, 3] = state.wn + d * (vn + 0.5 * slope * d)
        out[j, 4] = state.wfr + d * (v1 * d1 + v2 * d2) + 0.5 * d * d * (c1 * d1 + c2 * d2)
        out[j, 5] = phase
        j += 1
    return out, i_s
