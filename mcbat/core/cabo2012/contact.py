"""The contact problem in the normal impulse ``I``: slip, stick, re-slip and separation.

Everything here works in the contact basis ``(t1, t2, t3)``. The state is the impulse
``P = (P1, P2, I)`` delivered to the ball; the relative contact velocity is linear in it,
``v = v0 + K P``. See ``README.md`` in this folder for the equations.

Phases
------
slip
    ``dP_t/dI = -mu u``, ``u = v_t/|v_t|``, integrated by classical RK4 in ``I`` (plus the
    works ``W_n``, ``W_fr``). The right-hand side depends only on the slip direction ``u``,
    so RK4 is exact while ``u`` is constant; the only nonlinearity is the turning of ``u``.
    The step is ``h = min(I_scale / steps, 0.8 d, 0.8 |v_t| / (mu lambda_max(K_tt)),
    (eps d^3 / (mu omega))^(1/5))`` (the third term keeps RK4 stable: the slip direction
    relaxes at the rate ``mu K_tt / |v_t|``) with
    ``d`` the predicted impulse left until ``v_t = 0``, ``omega = |du/dI|`` and ``eps`` the
    impulse error allowed per step (``tolerance * I_scale``): a model of the RK4 local
    error ``~ mu omega h^5 / d^3``. Far from stick and with a steady direction this is the
    fixed step ``I_scale / steps``.
zero-slip detection
    No RK4 stage may pass the singular point ``v_t = 0`` (``h <= 0.8 d``), so the steps
    shrink geometrically towards it; once the direction has settled
    (``mu omega d^2 <= LANDING_FRACTION eps``) the last stretch is exact linear
    extrapolation. This locates the stick impulse ``I_s`` at 4th order in the step count
    (a naive RK4 through the stick point converges at first order: see
    ``tests/core/test_convergence.py``).
stick, re-slip and ``mu = 0``
    ``dP_t/dI`` is constant (``f = -K_tt^-1 K_tn``, ``-mu u*``, or 0): closed forms.

Compression ends at ``v_n = 0`` (``I_c``, ``W_c``); separation is the energetic rule
``W_n(I_f) = (1 - e*^2) W_c``. Events inside a step are located on the RK4 solution itself.
Every loop is bounded; failures return a status code and nothing raises.
"""

import math
from collections import namedtuple

from mcbat.core import status as st
from mcbat.core.jit import njit

__all__ = ["Accuracy", "Contact", "ContactResult", "SlipState",
           "after_slip", "failed_contact", "remove_residual_slip", "reslip_direction",
           "rk4_step", "slip_point", "slip_step_size", "slip_velocity", "velocity",
           "APPROACH_FACTOR", "APPROACH_MARGIN", "DEFAULT_MAX_STEPS", "DEFAULT_STEPS",
           "DEFAULT_TOLERANCE", "EVENT_MAX_ITER", "EVENT_TOLERANCE", "LANDING_FRACTION",
           "MAX_SLIP_FRACTION", "RESLIP_SAMPLES", "ROBUST_STICK", "STICK_TOLERANCE",
           "inverse_slip_stiffness", "solve_contact", "stick_impulse_rate"]

# Slip speed (relative to the initial relative speed) treated as exactly zero.
STICK_TOLERANCE = 1e-13
# Largest fraction of the predicted remaining slip length taken in one step: no RK4 stage
# may evaluate the direction past v_t = 0.
MAX_SLIP_FRACTION = 0.8
# Land on the stick point by linear extrapolation once the impulse error of doing so,
# ~ mu * omega * d^2, is below this fraction of the per-step budget.
LANDING_FRACTION = 0.3
# When sliding is predicted to stop before APPROACH_MARGIN of the impulse left until
# separation, the per-step budget grows by APPROACH_FACTOR: after stick, v_t = 0 fixes the
# tangential impulse from I alone, so errors made on the way in barely reach the outgoing
# velocities (measured on a 3000-impact mix against a converged run: the velocity error
# stays below the tolerance while the steps drop from 45 to 16 per impact at tolerance
# 1e-8). The works W_n, W_fr do keep
# those errors: they are good to ~1e-5 E_in at the default tolerance.
APPROACH_FACTOR = 3000.0
APPROACH_MARGIN = 0.5
ROBUST_STICK = 0.5  # |f| <= ROBUST_STICK * mu for the relaxed budget
# Events (end of compression, separation) are located to this fraction of I_scale.
EVENT_TOLERANCE = 1e-14
# Root finding for events inside a step.
EVENT_MAX_ITER = 60
# Re-slip direction search: azimuth samples before bisection.
RESLIP_SAMPLES = 72

DEFAULT_STEPS = 8
"""Steps per ``I_scale = 2 |v_n0| / K_33`` (the frictionless elastic impulse), at most."""
DEFAULT_TOLERANCE = 5e-9
"""Impulse error allowed per slip step, relative to ``I_scale``. Gives outgoing velocities
within ~3e-9 of |v0| on random 3D impacts (``benchmarks/bench_kernel.py``,
``tests/core/test_reference_crosscheck.py``)."""
DEFAULT_MAX_STEPS = 20_000
"""Bound on RK4 steps per impact; reaching it returns ``status.MAX_STEPS``."""


Contact = namedtuple("Contact", ["k11", "k12", "k13", "k22", "k23", "k33",
                                 "v01", "v02", "v0n", "mu"])
Contact.__doc__ = """One contact problem: the Delassus matrix ``K`` in the contact basis
``(t1, t2, t3)`` (``k11 .. k33``, 1/kg), the relative contact velocity at incidence
(``v01, v02`` tangential, ``v0n`` normal, m/s) and the friction coefficient ``mu``."""

SlipState = namedtuple("SlipState", ["imp", "p1", "p2", "wn", "wfr"])
SlipState.__doc__ = """State of the contact along ``I``: the normal impulse ``imp`` and the
tangential impulses ``p1, p2`` delivered to the ball (kg m/s), the normal and friction works
``wn``, ``wfr`` done so far (J)."""

SlipPoint = namedtuple("SlipPoint", ["vn", "s", "u1", "u2", "g1", "g2", "dvn", "sigma",
                                     "omega"])
SlipPoint.__doc__ = """What the slip step rule needs at one state: normal velocity ``vn`` and
slip speed ``s`` (m/s), slip direction ``u``, the slip acceleration ``g = dv_t/dI`` and
``dvn = dv_n/dI`` (1/kg), ``sigma = d|v_t|/dI`` and ``omega = |du/dI|`` (1/(kg m/s))."""

Compression = namedtuple("Compression", ["done", "i_c", "w_c", "target"])
Compression.__doc__ = """The normal phase: whether compression has ended, at which impulse
``i_c`` and normal work ``w_c``, and the normal work at separation ``target``."""

Accuracy = namedtuple("Accuracy", ["steps", "tolerance", "max_steps"])
Accuracy.__doc__ = """Accuracy settings of :func:`solve_contact` (see its parameters)."""

ContactResult = namedtuple("ContactResult", [
    "status", "end_state", "p1", "p2", "i_f", "i_s", "i_c", "w_c", "w_n", "w_fr",
    "w_n_stick", "rk4_steps"])
ContactResult.__doc__ = """Result of :func:`solve_contact` (see its Returns)."""


@njit(inline="always")
def velocity(c, p1, p2, imp):
    """Relative contact velocity (m/s, contact frame) after the tangential impulse
    ``(p1, p2)`` and the normal impulse ``imp`` (kg m/s): ``v0 + K P``."""
    v1 = c.v01 + c.k11 * p1 + c.k12 * p2 + c.k13 * imp
    v2 = c.v02 + c.k12 * p1 + c.k22 * p2 + c.k23 * imp
    vn = c.v0n + c.k13 * p1 + c.k23 * p2 + c.k33 * imp
    return v1, v2, vn


@njit(inline="always")
def slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp):
    """:func:`velocity` from loose scalars (m/s)."""
    return velocity(Contact(k11, k12, k13, k22, k23, k33, v01, v02, v0n, 0.0), p1, p2, imp)


@njit(inline="always")
def slip_rates(c, p1, p2, imp):
    """Slip rates ``d(P1, P2, W_n, W_fr)/dI``."""
    v1, v2, vn = velocity(c, p1, p2, imp)
    s = math.sqrt(v1 * v1 + v2 * v2)
    k = c.mu / s
    return -k * v1, -k * v2, vn, -c.mu * s


@njit(inline="always")
def slip_point(c, state):
    """The slip direction, its rates and the slip speed at ``state`` (:class:`SlipPoint`)."""
    v1, v2, vn = velocity(c, state.p1, state.p2, state.imp)
    s = math.sqrt(v1 * v1 + v2 * v2)
    inv_s = 1.0 / s
    u1 = v1 * inv_s
    u2 = v2 * inv_s
    g1 = c.k13 - c.mu * (c.k11 * u1 + c.k12 * u2)  # d v_t / dI
    g2 = c.k23 - c.mu * (c.k12 * u1 + c.k22 * u2)
    dvn = c.k33 - c.mu * (c.k13 * u1 + c.k23 * u2)  # d v_n / dI
    sigma = u1 * g1 + u2 * g2  # d|v_t|/dI
    omega = abs(u1 * g2 - u2 * g1) * inv_s  # |du/dI|: how fast the slip direction turns
    return SlipPoint(vn, s, u1, u2, g1, g2, dvn, sigma, omega)


@njit(inline="always")
def rk4_step(c, state, h, rates):
    """One classical RK4 step of the slip ODE from ``state.imp`` to ``state.imp + h``.

    ``rates`` are the rates at the start (the first stage), which the caller already has.
    """
    a1, a2, a3, a4 = rates
    imp, p1, p2, wn, wfr = state
    hh = 0.5 * h
    b1, b2, b3, b4 = slip_rates(c, p1 + hh * a1, p2 + hh * a2, imp + hh)
    c1, c2, c3, c4 = slip_rates(c, p1 + hh * b1, p2 + hh * b2, imp + hh)
    d1, d2, d3, d4 = slip_rates(c, p1 + h * c1, p2 + h * c2, imp + h)
    w = h / 6.0
    return SlipState(
        imp + h,
        p1 + w * (a1 + 2.0 * (b1 + c1) + d1),
        p2 + w * (a2 + 2.0 * (b2 + c2) + d2),
        wn + w * (a3 + 2.0 * (b3 + c3) + d3),
        wfr + w * (a4 + 2.0 * (b4 + c4) + d4),
    )


@njit(inline="always")
def _point_rates(c, pt):
    """The slip rates at a :class:`SlipPoint`, without recomputing the direction."""
    return -c.mu * pt.u1, -c.mu * pt.u2, pt.vn, -c.mu * pt.s


@njit(inline="always")
def _remaining_impulse(vn, dvn, wn, compression, retained):
    """Impulse left until separation if ``v_n`` kept growing at the rate ``dvn`` (kg m/s)."""
    if not (dvn > 0.0):
        return math.inf
    target = compression.target
    if not compression.done:
        w_c = wn - 0.5 * vn * vn / dvn
        target = retained * w_c
    gap = max(target - wn, 0.0)
    return (-vn + math.sqrt(max(vn * vn + 2.0 * dvn * gap, 0.0))) / dvn


@njit(inline="always")
def slip_step_size(c, pt, h_max, budget, landing_budget, inv_mu_ktt, s_stop):
    """The slip step rule, shared by :func:`solve_contact` and ``contact_history``.

    Returns ``(h, land)``: the next step in ``I`` (kg m/s) and whether it lands on
    ``v_t = 0`` by linear extrapolation. ``budget`` is the impulse error allowed in the
    step, ``landing_budget`` the one the landing must meet (kg m/s).
    """
    h = h_max
    if pt.sigma < 0.0:
        dist = pt.s / (-pt.sigma)  # predicted impulse left until v_t = 0
        length = dist
        if pt.s <= s_stop or c.mu * pt.omega * dist * dist <= LANDING_FRACTION * landing_budget:
            # The direction has settled: v_t falls linearly to zero. Assuming so costs
            # about mu * (turn left ~ omega * dist) * dist of impulse.
            return dist, True
        h = min(h, MAX_SLIP_FRACTION * dist)  # no RK4 stage may pass v_t = 0
    else:
        length = pt.s / math.sqrt(pt.g1 * pt.g1 + pt.g2 * pt.g2)  # I over which v_t doubles
    # The slip direction relaxes at the rate ~ mu K_tt / |v_t| (the Jacobian of the slip
    # ODE): a longer step is unstable and can freeze a spurious sliding mode near v_t = 0.
    h = min(h, MAX_SLIP_FRACTION * pt.s * inv_mu_ktt)
    if pt.omega > 0.0:
        # RK4 local error ~ mu * omega * h^5 / length^3 (the turning slip direction is the
        # only nonlinearity); keep it below the budget.
        h = min(h, (budget * length ** 3 / (c.mu * pt.omega)) ** 0.2)
    return h, False


@njit(inline="always")
def _linear_slip(c, state, pt, h):
    """Slip at the constant rates of ``pt`` over ``h``: exact while ``v_t`` falls linearly
    to zero (the landing), with the friction work of that linear fall."""
    return SlipState(state.imp + h, state.p1 - c.mu * pt.u1 * h, state.p2 - c.mu * pt.u2 * h,
                     state.wn + h * (pt.vn + 0.5 * pt.dvn * h),
                     state.wfr - c.mu * h * (pt.s - 0.5 * (-pt.sigma) * h))


@njit(inline="always")
def _advance(c, state, pt, h, land):
    """The step of length ``h`` chosen by :func:`slip_step_size`."""
    if land:
        return SlipState(state.imp + h, state.p1 - c.mu * pt.u1 * h,
                         state.p2 - c.mu * pt.u2 * h,
                         state.wn + h * (pt.vn + 0.5 * pt.dvn * h),
                         state.wfr - 0.5 * c.mu * pt.s * h)
    return rk4_step(c, state, h, _point_rates(c, pt))


@njit(inline="always")
def _hermite_root(g0, g1, m0, m1):
    """Root in [0, 1] of the cubic Hermite interpolant with values ``g0 < 0 <= g1`` and
    slopes ``m0, m1`` at the ends (Newton's method, safeguarded by bisection)."""
    lo = 0.0
    hi = 1.0
    t = g0 / (g0 - g1)
    for _ in range(EVENT_MAX_ITER):
        t2 = t * t
        t3 = t2 * t
        val = ((2.0 * t3 - 3.0 * t2 + 1.0) * g0 + (t3 - 2.0 * t2 + t) * m0
               + (-2.0 * t3 + 3.0 * t2) * g1 + (t3 - t2) * m1)
        der = ((6.0 * t2 - 6.0 * t) * g0 + (3.0 * t2 - 4.0 * t + 1.0) * m0
               + (-6.0 * t2 + 6.0 * t) * g1 + (3.0 * t2 - 2.0 * t) * m1)
        if val < 0.0:
            lo = t
        else:
            hi = t
        new = t - val / der if der != 0.0 else -1.0
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        if abs(new - t) <= 1e-15:
            return new
        t = new
    return t


@njit
def _locate_event(c, state, h, kind, target, g0, g1, d0, d1, tol_imp):
    """Locate an event inside the RK4 step ``[imp, imp + h]`` from ``state``.

    ``kind`` 0: end of compression, ``g = v_n``; 1: separation, ``g = W_n - target``.
    ``g0 < 0 <= g1`` at the ends, ``d0, d1`` their derivatives in ``I``. The cubic Hermite
    interpolant of ``g`` (4th-order accurate, like the step) gives the first guess; Newton's
    method on the RK4 solution itself (partial steps from ``imp``) then polishes it to
    ``tol_imp`` in impulse, safeguarded by bisection. Returns the state at the event.
    """
    lo = 0.0
    hi = 1.0
    theta = _hermite_root(g0, g1, d0 * h, d1 * h)
    rates = slip_rates(c, state.p1, state.p2, state.imp)
    out = SlipState(state.imp + h, state.p1, state.p2, state.wn, state.wfr)
    for _ in range(EVENT_MAX_ITER):
        out = rk4_step(c, state, theta * h, rates)
        v1, v2, vn = velocity(c, out.p1, out.p2, out.imp)
        if kind == 0:
            q1, q2, q3, q4 = slip_rates(c, out.p1, out.p2, out.imp)
            g = vn
            dg = (c.k13 * q1 + c.k23 * q2 + c.k33) * h
        else:
            g = out.wn - target
            dg = vn * h
        if g == 0.0:
            break
        if g < 0.0:
            lo = theta
        else:
            hi = theta
        new = theta - g / dg if dg != 0.0 else -1.0
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        done = abs(new - theta) * h <= tol_imp or (hi - lo) * h <= tol_imp
        theta = new
        if done:
            out = rk4_step(c, state, theta * h, rates)
            break
    return out


@njit(inline="always")
def _end_of_compression(c, state, pt, h, land, new, n_vn, tol_imp):
    """The state at ``v_n = 0`` inside the step ``h`` from ``state`` to ``new`` (where
    ``v_n = n_vn >= 0``)."""
    if land:
        # Linear in I on this step: the crossing is explicit.
        return _linear_slip(c, state, pt, (-pt.vn / (n_vn - pt.vn)) * h)
    e1, e2, _, _ = slip_rates(c, new.p1, new.p2, new.imp)
    return _locate_event(c, state, h, 0, 0.0, pt.vn, n_vn, pt.dvn,
                         c.k13 * e1 + c.k23 * e2 + c.k33, tol_imp)


@njit(inline="always")
def _separation(c, state, pt, h, land, new, n_vn, target, tol_imp):
    """The state at ``W_n = target`` inside the step ``h`` from ``state`` to ``new``."""
    if land:
        # W_n is quadratic in I on this step.
        a = 0.5 * pt.dvn
        gap = state.wn - target
        disc = pt.vn * pt.vn - 4.0 * a * gap
        root = math.sqrt(max(disc, 0.0))
        h = (2.0 * (-gap)) / (pt.vn + root) if pt.vn + root > 0.0 else h
        return _linear_slip(c, state, pt, h)
    return _locate_event(c, state, h, 1, target, state.wn - target, new.wn - target, pt.vn,
                         n_vn, tol_imp)


@njit(inline="always")
def remove_residual_slip(c, state):
    """After a landing: the tangential impulse that makes ``v_t = 0`` exactly at ``I_s``.

    The landing bounds the impulse error; ``K_tt`` turns it into a residual slip that the
    stick phase would carry to the end (and let friction work on it).
    """
    r1, r2, _ = velocity(c, state.p1, state.p2, state.imp)
    det = c.k11 * c.k22 - c.k12 * c.k12
    if not det > 0.0:
        return state
    q1 = (c.k22 * r1 - c.k12 * r2) / det
    q2 = (c.k11 * r2 - c.k12 * r1) / det
    return SlipState(state.imp, state.p1 - q1, state.p2 - q2, state.wn,
                     state.wfr - 0.5 * (r1 * q1 + r2 * q2))  # the kinetic energy it takes out


@njit
def _slip_phase(c, acc, retained):
    """Slip from incidence until ``v_t = 0`` or separation: RK4 in ``I`` with zero-slip
    detection and the compression and separation events.

    Returns ``(status, state, compression, separated, rk4_steps)``.
    """
    v_scale = math.sqrt(c.v01 * c.v01 + c.v02 * c.v02 + c.v0n * c.v0n)
    s_stop = STICK_TOLERANCE * v_scale
    i_scale = 2.0 * (-c.v0n) / c.k33  # frictionless, fully elastic impact impulse
    h_max = i_scale / acc.steps
    error_per_step = acc.tolerance * i_scale  # impulse error allowed per slip step, kg m/s
    event_tolerance = EVENT_TOLERANCE * i_scale
    inv_mu_ktt = inverse_slip_stiffness(c.k11, c.k12, c.k22, c.mu)
    # The relaxed budget on the way into a stick needs a stick that holds with margin: near
    # |f| = mu the outcome (stick or re-slip) depends on exactly how slip dies out.
    f1, f2 = stick_impulse_rate(c.k11, c.k12, c.k13, c.k22, c.k23)
    robust_stick = f1 * f1 + f2 * f2 <= (ROBUST_STICK * c.mu) ** 2
    approach = False  # set once sliding is predicted to stop well before separation
    state = SlipState(0.0, 0.0, 0.0, 0.0, 0.0)
    comp = Compression(False, math.nan, math.nan, math.nan)
    n_rk4 = 0
    n_iter = 0  # every pass, RK4 or not: the loop is bounded whatever happens
    while True:
        n_iter += 1
        if n_rk4 >= acc.max_steps or n_iter > acc.max_steps + 8:
            return st.MAX_STEPS, state, comp, True, n_rk4
        pt = slip_point(c, state)
        budget = error_per_step
        if pt.sigma < 0.0:
            if not approach and robust_stick:
                approach = pt.s / (-pt.sigma) < APPROACH_MARGIN * _remaining_impulse(
                    pt.vn, pt.dvn, state.wn, comp, retained)
            if approach:
                # Sliding will stop well before separation. After stick the constraint
                # v_t = 0 fixes the tangential impulse from I alone, so errors made on the way
                # in are mostly forgotten: a looser budget costs no accuracy in the result.
                budget = APPROACH_FACTOR * error_per_step
        h, land = slip_step_size(c, pt, h_max, budget, error_per_step, inv_mu_ktt, s_stop)
        new = _advance(c, state, pt, h, land)
        if not land:
            n_rk4 += 1
        n_vn = velocity(c, new.p1, new.p2, new.imp)[2]
        if not comp.done and n_vn >= 0.0:
            state = _end_of_compression(c, state, pt, h, land, new, n_vn, event_tolerance)
            comp = Compression(True, state.imp, state.wn, retained * state.wn)
            if retained == 1.0:
                return st.OK, state, comp, True, n_rk4  # e* = 0: separation at once
            continue
        if comp.done and new.wn >= comp.target:
            end = _separation(c, state, pt, h, land, new, n_vn, comp.target, event_tolerance)
            return st.OK, end, comp, True, n_rk4
        state = new
        if land:
            return st.OK, remove_residual_slip(c, state), comp, False, n_rk4


@njit
def reslip_direction(k11, k12, k13, k22, k23, mu):
    """Direction ``u*`` of re-slip after a failed stick, and its rate ``lambda`` > 0.

    Solves ``K_tn - mu K_tt u = lambda u`` on the unit circle (Stronge; Bhatt & Koechling):
    the sign changes of ``u x g(u)`` are bracketed on a grid and bisected. Among the roots
    with ``lambda > 0`` the one with the largest ``lambda`` is returned. ``(nan, nan, -1)``
    if there is none.
    """
    best_u1 = math.nan
    best_u2 = math.nan
    best_lam = -1.0
    step = 2.0 * math.pi / RESLIP_SAMPLES

    def cross_fn(phi):
        u1 = math.cos(phi)
        u2 = math.sin(phi)
        g1 = k13 - mu * (k11 * u1 + k12 * u2)
        g2 = k23 - mu * (k12 * u1 + k22 * u2)
        return u1 * g2 - u2 * g1

    # Offset the grid so symmetric roots (e.g. exactly +-pi/2) fall inside intervals.
    a = 0.123456789 * step
    fa = cross_fn(a)
    for _ in range(RESLIP_SAMPLES):
        b = a + step
        fb = cross_fn(b)
        if fa == 0.0 or fa * fb < 0.0:
            lo = a
            hi = b
            flo = fa
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                fm = cross_fn(mid)
                if (fm < 0.0) == (flo < 0.0) and fm != 0.0:
                    lo = mid
                    flo = fm
                else:
                    hi = mid
            phi = 0.5 * (lo + hi)
            u1 = math.cos(phi)
            u2 = math.sin(phi)
            lam = u1 * (k13 - mu * (k11 * u1 + k12 * u2)) + u2 * (k23 - mu * (k12 * u1 + k22 * u2))
            if lam > best_lam:
                best_lam = lam
                best_u1 = u1
                best_u2 = u2
        a = b
        fa = fb
    if best_lam <= 0.0:
        return math.nan, math.nan, -1.0
    return best_u1, best_u2, best_lam


@njit(inline="always")
def inverse_slip_stiffness(k11, k12, k22, mu):
    """``1 / (mu lambda_max(K_tt))`` (kg): the slip direction relaxes at the rate
    ``mu K_tt / |v_t|``, so an RK4 step must stay below ~``|v_t|`` times this (inf if
    ``mu = 0``)."""
    if not mu > 0.0:
        return math.inf
    return 1.0 / (mu * (0.5 * (k11 + k22) + math.sqrt(0.25 * (k11 - k22) ** 2 + k12 * k12)))


@njit
def stick_impulse_rate(k11, k12, k13, k22, k23):
    """Tangential impulse rate ``f = -K_tt^-1 K_tn`` that holds ``v_t = 0`` (dimensionless)."""
    det = k11 * k22 - k12 * k12
    f1 = -(k22 * k13 - k12 * k23) / det
    f2 = -(k11 * k23 - k12 * k13) / det
    return f1, f2


@njit
def after_slip(c):
    """Once slip has stopped: stick, re-slip or frictionless sliding.

    Returns ``(status, end_state, d1, d2)`` with ``(d1, d2) = dP_t/dI`` from here on: the
    stick rate ``f = -K_tt^-1 K_tn``, ``-mu u*`` along the re-slip direction, or 0.
    """
    if not c.mu > 0.0:
        return st.OK, st.SLIDING, 0.0, 0.0  # the end state is settled by the final v_t
    f1, f2 = stick_impulse_rate(c.k11, c.k12, c.k13, c.k22, c.k23)
    if f1 * f1 + f2 * f2 <= c.mu * c.mu:
        return st.OK, st.STUCK, f1, f2
    u1, u2, lam = reslip_direction(c.k11, c.k12, c.k13, c.k22, c.k23, c.mu)
    if lam <= 0.0:
        return st.DEGENERATE, st.SLIDING, 0.0, 0.0
    return st.OK, st.SLIDING, -c.mu * u1, -c.mu * u2


@njit(inline="always")
def _linear_phase(c, state, comp, d1, d2, e):
    """To separation at the constant rates ``dP/dI = (d1, d2, 1)``: ``W_n`` is quadratic
    in ``I``, so the end of compression and the separation are closed forms.

    Returns ``(ok, state, compression, (v1, v2))``, the last the tangential velocity at
    separation; ``ok`` is False if ``v_n`` does not grow.
    """
    v1, v2, vn = velocity(c, state.p1, state.p2, state.imp)
    slope = c.k13 * d1 + c.k23 * d2 + c.k33  # d v_n / dI
    if not (slope > 0.0):
        return False, state, comp, (v1, v2)
    c1 = c.k11 * d1 + c.k12 * d2 + c.k13  # d v_t / dI
    c2 = c.k12 * d1 + c.k22 * d2 + c.k23
    if not comp.done:
        # Compression ends in this phase; W_n = W_c + slope/2 (I - I_c)^2 about the vertex.
        i_c = state.imp - vn / slope
        w_c = state.wn - 0.5 * vn * vn / slope
        comp = Compression(True, i_c, w_c, (1.0 - e * e) * w_c)
        dh = (i_c - state.imp) + math.sqrt(2.0 * (e * e) * (-w_c) / slope)
    else:
        gap = comp.target - state.wn  # >= 0 while still in contact
        if gap <= 0.0:
            dh = 0.0
        else:
            dh = 2.0 * gap / (vn + math.sqrt(vn * vn + 2.0 * slope * gap))
    end = SlipState(
        state.imp + dh, state.p1 + d1 * dh, state.p2 + d2 * dh,
        state.wn + dh * (vn + 0.5 * slope * dh),
        state.wfr + (dh * (v1 * d1 + v2 * d2) + 0.5 * dh * dh * (c1 * d1 + c2 * d2)))
    return True, end, comp, (v1 + c1 * dh, v2 + c2 * dh)


@njit(inline="always")
def failed_contact(code, rk4_steps=0):
    """The one place a failed :class:`ContactResult` is built: every output NaN."""
    nan = math.nan
    return ContactResult(code, st.SLIDING, nan, nan, nan, nan, nan, nan, nan, nan, nan,
                         rk4_steps)


@njit(inline="always")
def _valid_contact(c, e, acc):
    """Finite inputs in their ranges (NaN fails every comparison)."""
    return (math.isfinite(c.k11) and math.isfinite(c.k12) and math.isfinite(c.k13)
            and math.isfinite(c.k22) and math.isfinite(c.k23) and math.isfinite(c.k33)
            and math.isfinite(c.v01) and math.isfinite(c.v02) and math.isfinite(c.v0n)
            and math.isfinite(c.mu) and math.isfinite(e)
            and c.mu >= 0.0 and 0.0 <= e <= 1.0 and c.k33 > 0.0
            and c.k11 * c.k22 - c.k12 * c.k12 > 0.0 and acc.steps >= 1
            and 0.0 < acc.tolerance < 1.0)


@njit
def solve_contact(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, e,
                  steps=DEFAULT_STEPS, tolerance=DEFAULT_TOLERANCE,
                  max_steps=DEFAULT_MAX_STEPS):
    """Solve one impact in the contact basis.

    Parameters
    ----------
    k11, k12, k13, k22, k23, k33 : float
        Delassus matrix in the ``(t1, t2, t3)`` basis, 1/kg.
    v01, v02, v0n : float
        Initial relative contact velocity (tangential 1, 2 and normal), m/s. ``v0n < 0``.
    mu : float
        Coulomb friction coefficient, >= 0.
    e : float
        Energetic coefficient of restitution ``e*`` in [0, 1].
    steps : int
        At least this many RK4 steps per ``I_scale = 2 |v0n| / K_33`` (the step cap).
    tolerance : float
        Impulse error allowed per slip step, relative to ``I_scale``; in (0, 1). The
        accuracy knob: errors scale with it, the step count with its -1/5 power.
    max_steps : int
        Bound on RK4 steps; exceeding it returns ``MAX_STEPS``.

    Returns
    -------
    ContactResult
        ``(status, end_state, p1, p2, i_f, i_s, i_c, w_c, w_n, w_fr, w_n_stick,
        rk4_steps)``: tangential impulses ``P1, P2`` and normal impulse ``I_f`` (kg m/s) at
        separation; the stick impulse ``I_s`` (NaN if sliding never stopped; 0 for
        incidence with ``v_t = 0``); the end of compression ``I_c`` and ``W_c = W_n(I_c)``;
        the normal and friction work at separation (J); ``W_n(I_s)`` (the paper's
        ``C = -W_n(I_s)``); and the number of RK4 steps taken. On a failure status every
        physical output is NaN (:func:`failed_contact`).
    """
    c = Contact(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu)
    acc = Accuracy(steps, tolerance, max_steps)
    if not _valid_contact(c, e, acc):
        return failed_contact(st.INVALID_INPUT)
    if not (v0n < 0.0):
        return failed_contact(st.NOT_APPROACHING)
    retained = 1.0 - e * e  # W_n(I_f) = retained * W_c
    s_stop = STICK_TOLERANCE * math.sqrt(v01 * v01 + v02 * v02 + v0n * v0n)
    state = SlipState(0.0, 0.0, 0.0, 0.0, 0.0)
    comp = Compression(False, math.nan, math.nan, math.nan)
    n_rk4 = 0
    if mu > 0.0 and math.sqrt(v01 * v01 + v02 * v02) > s_stop:
        code, state, comp, separated, n_rk4 = _slip_phase(c, acc, retained)
        if code != st.OK:
            return failed_contact(code)
        if separated:
            return ContactResult(st.OK, st.SLIDING, state.p1, state.p2, state.imp, math.nan,
                                 comp.i_c, comp.w_c, state.wn, state.wfr, math.nan, n_rk4)
    i_s = state.imp if mu > 0.0 else math.nan
    wn_s = state.wn if mu > 0.0 else math.nan
    code, end_state, d1, d2 = after_slip(c)
    if code != st.OK:
        return failed_contact(code)
    ok, state, comp, slip = _linear_phase(c, state, comp, d1, d2, e)
    if not ok:
        return failed_contact(st.DEGENERATE)
    if mu == 0.0:
        # Without friction v_t still drifts through K_tn; report what it ends at.
        if math.sqrt(slip[0] * slip[0] + slip[1] * slip[1]) <= s_stop:
            end_state = st.STUCK
    return ContactResult(st.OK, end_state, state.p1, state.p2, state.imp, i_s, comp.i_c,
                         comp.w_c, state.wn, state.wfr, wn_s, n_rk4)
