"""The history of one impact along the normal impulse ``I``, for plots and diagnostics.

``contact_history`` evaluates the relative contact velocity and the works at given
impulses, following the same phases as ``mcbat.core.cabo2012.contact.solve_contact``
(Lawson RK4 slip in ``tau`` with the same error control, on a finer step cap, the points
located inside the steps; then the stick or re-slip closed form). It does not stop
at separation: the curves continue past ``I_f`` so that plots can show where the
separation rules cut them.
"""

import math

import numpy as np

from mcbat.core import status as st
from mcbat.core.cabo2012.contact import (
    DEFAULT_TOLERANCE,
    LAND_ACTION,
    STOP_ACTION,
    Contact,
    SlipState,
    after_slip,
    error_ratio,
    linear_slip,
    locate_in_step,
    next_step,
    normal_work,
    remove_residual_slip,
    resized_step,
    slip_control,
    slip_point,
    slip_state,
    step_plan,
    velocity,
)
from mcbat.core.cabo2012.slip_time import tau_point, tau_step
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
    # The solver's step rule, on finer steps (also relative to the span plotted), so that
    # the curves are smooth.
    per_scale = 1.0 / 256.0
    if n and impulses[n - 1] > 0.0:
        per_scale = min(per_scale, impulses[n - 1] / 512.0 / (2.0 * abs(v0n) / k33))
    ctl = slip_control(c, tolerance, per_scale)
    w1, w2 = v01, v02
    state = SlipState(0.0, 0.0, 0.0, 0.0, 0.0)
    i_s = math.nan
    j = 0
    h = math.inf
    # ---- slip, recorded at the requested impulses inside the steps ----
    last_h = 0.0  # the last accepted step and its error ratio, as in the solver
    last_ratio = 0.0
    passes = 0
    while j < n and mu > 0.0:
        passes += 1
        if passes > MAX_HISTORY_STEPS:
            return out, i_s  # bounded: the remaining points stay NaN
        pt = tau_point(c, w1, w2)
        action, h, stick_rate, tol_i = step_plan(ctl, pt, state.imp, h, passes == 1)
        if action == STOP_ACTION:
            state = remove_residual_slip(c, state)
            break
        if action == LAND_ACTION:  # land: v_t falls linearly to zero, as in the solver
            sp = slip_point(c, state)
            dist = sp.s / (-sp.sigma)
            while j < n and impulses[j] <= state.imp + dist:
                _record(out, j, c, linear_slip(c, state, sp, impulses[j] - state.imp), SLIP)
                j += 1
            state = remove_residual_slip(c, linear_slip(c, state, sp, dist))
            break
        step = tau_step(c, w1, w2, state.imp, state.wfr, -pt.rate, h)
        ratio = error_ratio(ctl, step, stick_rate, tol_i)
        if ratio > 1.0:
            h = resized_step(h, ratio)
            last_h = 0.0
            continue
        while j < n and impulses[j] <= step.imp:
            part = state
            if impulses[j] > state.imp:
                # (np.int64: the solver's compiled locate_in_step, not one for a constant)
                _, part, _ = locate_in_step(c, state, w1, w2, -pt.rate, h, np.int64(2),
                                            impulses[j], 0.0, step, 1e-15 * ctl.i_scale)
            _record(out, j, c, part, SLIP)
            j += 1
        new = slip_state(c, step.w1, step.w2, step.imp, step.wfr, 0.0)
        state = SlipState(new.imp, new.p1, new.p2,
                          state.wn + normal_work(c, state, new, step),
                          new.wfr)
        w1, w2 = step.w1, step.w2
        h, last_h, last_ratio = next_step(h, ratio, last_h, last_ratio), h, ratio
    if j >= n:
        return out, i_s
    imp = state.imp
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
        d = impulses[j] - imp
        out[j, 0] = v1 + c1 * d
        out[j, 1] = v2 + c2 * d
        out[j, 2] = vn + slope * d
        out[j, 3] = state.wn + d * (vn + 0.5 * slope * d)
        out[j, 4] = state.wfr + d * (v1 * d1 + v2 * d2) + 0.5 * d * d * (c1 * d1 + c2 * d2)
        out[j, 5] = phase
        j += 1
    return out, i_s
