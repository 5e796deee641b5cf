"""The contact problem along the normal impulse ``I``: slip, stick, re-slip and separation.

Everything here works in the contact basis ``(t1, t2, t3)``. The state is the impulse
``P = (P1, P2, I)`` delivered to the ball; the relative contact velocity is linear in it,
``v = v0 + K P``. See ``README.md`` in this folder for the equations.

Phases
------
slip
    ``dP_t/dI = -mu u``, ``u = v_t/|v_t|``, integrated in the slip-scaled time ``tau``
    (``dI = |v_t| dtau``) by Lawson RK4 (``mcbat.core.cabo2012.slip_time``): smooth up
    to the stick point, which ``tau`` reaches only exponentially, and exact while the slip
    direction is constant. The step is controlled a posteriori by the embedded error
    estimate: per step, ``tolerance`` times ``|v0|`` in the slip velocity, times ``I_scale``
    in the impulse and times ``|v0| I_scale`` in the friction work, and at most
    ``I_scale / steps`` of impulse. ``P_t`` follows from ``I`` and ``v_t`` algebraically;
    ``W_n`` is integrated on its own (``normal_work``).
landing on ``v_t = 0``
    Once the error of taking the rest as linear in ``I`` is below
    ``LANDING_FRACTION * tolerance * I_scale`` (the impulse left, ``|v_t| / (-d|v_t|/dI)``,
    times the relative change of ``d|v_t|/dI`` over the turn the direction has left), the
    rest is linear (closed form, events included) and the tangential impulse is set so
    that ``v_t = 0`` exactly. The step also stays within RK4's stability limit
    (``STABLE_STEP``), which the error estimate stops enforcing once the direction settles.
stick, re-slip and ``mu = 0``
    ``dP_t/dI`` is constant (``f = -K_tt^-1 K_tn``, ``-mu u*``, or 0): closed forms.

Compression ends at ``v_n = 0`` (``I_c``, ``W_c``); separation is the energetic rule
``W_n(I_f) = (1 - e*^2) W_c``. Events inside a step are located on the step's own solution
(partial steps). Every loop is bounded; failures return a status code and nothing raises.
"""

import math
from collections import namedtuple

import numpy as np

from mcbat.core import status as st
from mcbat.core.cabo2012.slip_time import tau_point, tau_step
from mcbat.core.jit import njit

__all__ = ["Accuracy", "Compression", "Contact", "ContactResult", "NOT_COMPRESSED",
           "SlipState",
           "after_slip", "failed_contact", "impulse_step_cap", "linear_slip", "locate_in_step",
           "normal_work",
           "error_ratio", "next_step", "remove_residual_slip", "reslip_direction", "resized_step",
           "slip_control", "slip_point", "slip_state", "step_plan", "SlipControl",
           "solve_contact", "stick_impulse_rate", "velocity",
           "DEFAULT_ACCURACY", "DEFAULT_MAX_STEPS", "DEFAULT_STEPS", "DEFAULT_TOLERANCE",
           "EVENT_MAX_ITER", "EVENT_TOLERANCE", "LANDING_FRACTION", "RESLIP_SAMPLES",
           "SLIP_RESOLUTION", "STABLE_STEP", "STICK_TOLERANCE",
           "STEP_ACTION", "LAND_ACTION", "STOP_ACTION"]

# Slip speed (relative to the initial relative speed) treated as exactly zero.
STICK_TOLERANCE = 1e-13
# Slip speed (relative to the initial relative speed) below which the slip direction is not
# resolved: slip that starts below it, or whose speed passes a minimum below it, has
# stopped there (stick, or re-slip in the re-slip direction). A near miss that close is the
# same impact as a stop and re-slip to ~1e-11 in every velocity, but passing through it
# means following a direction that turns at the rate mu K_tt / |v_t|, for hundreds of
# steps, and reporting no I_s where the reference solver, which uses the same definition
# (mcbat.testing.cabo2012_reference.SLIP_STOP_FRACTION), reports one.
SLIP_RESOLUTION = 1e-10
# Land on v_t = 0 by linear extrapolation once the error of doing so (the impulse left,
# times the relative change of d|v_t|/dI over the turn the direction has left) is below
# this fraction of the impulse tolerance. Small, because that estimate is the landing's
# actual error, while a step's embedded estimate bounds the third-order solution and the
# kept fourth-order one errs far less: with a fraction near 1 (0.3, say) the landing
# dominates I_s in creeping slip, and since it happens at the first step below the
# threshold its error jumps up and down as the tolerance changes (I_s converges
# non-monotonically in 5 of the 520 cases of validation/kernel_accuracy.py). 0.003 costs 0.8
# steps per impact on that mix against 0.3 (0.3 steps on a batting study's).
LANDING_FRACTION = 0.003
# Largest step in tau times the spectral radius of the Jacobian of the Lawson equation: RK4
# is stable to ~2.8 on the real and imaginary axes. Once the direction has settled the
# error estimate no longer limits the step, and beyond this the settled direction would
# oscillate instead of relaxing.
STABLE_STEP = 2.5
# Events (end of compression, separation) are located to this fraction of I_scale.
EVENT_TOLERANCE = 1e-14
# Root finding for events inside a step.
EVENT_MAX_ITER = 60
# Re-slip direction search: azimuth samples before bisection.
RESLIP_SAMPLES = 72

# The actions of the slip step rule (step_plan): take a step, land on v_t = 0 by linear
# extrapolation, or stop where the slip is. Module-level ints, so numba compiles them in as
# constants.
STEP_ACTION = 0
LAND_ACTION = 1
STOP_ACTION = 2

DEFAULT_STEPS = 8
"""Steps per ``I_scale = 2 |v_n0| / K_33`` (the frictionless elastic impulse), at least."""
DEFAULT_TOLERANCE = 5e-9
"""Local error allowed per slip step, relative to ``|v0|`` (slip velocity), ``I_scale``
(impulse) and ``|v0| I_scale`` (friction work)."""
DEFAULT_MAX_STEPS = 20_000
"""Bound on slip steps per impact (rejected ones included); reaching it returns
``status.MAX_STEPS``."""


Contact = namedtuple("Contact", ["k11", "k12", "k13", "k22", "k23", "k33",
                                 "v01", "v02", "v0n", "mu"])
Contact.__doc__ = """One contact problem: the Delassus matrix ``K`` in the contact basis
``(t1, t2, t3)`` (``k11 .. k33``, 1/kg), the relative contact velocity at incidence
(``v01, v02`` tangential, ``v0n`` normal, m/s) and the friction coefficient ``mu``."""

SlipState = namedtuple("SlipState", ["imp", "p1", "p2", "wn", "wfr"])
SlipState.__doc__ = """State of the contact along ``I``: the normal impulse ``imp`` and the
tangential impulses ``p1, p2`` delivered to the ball (kg m/s), the normal and friction works
``wn``, ``wfr`` done so far (J)."""

SlipPoint = namedtuple("SlipPoint", ["vn", "s", "u1", "u2", "g1", "g2", "dvn", "sigma"])
SlipPoint.__doc__ = """The slip at one state, in ``I``: normal velocity ``vn`` and
slip speed ``s`` (m/s), slip direction ``u``, the slip acceleration ``g = dv_t/dI`` and
``dvn = dv_n/dI`` (1/kg) and ``sigma = d|v_t|/dI`` (1/kg)."""

Compression = namedtuple("Compression", ["done", "i_c", "w_c", "target", "rise"])
Compression.__doc__ = """The normal phase: whether compression has ended, at which impulse
``i_c`` and normal work ``w_c``; the normal work at separation ``target`` and how much
``W_n`` rises from ``w_c`` to it, ``rise = -e*^2 w_c`` (J). The kernel tracks the normal
work since compression on its own, so that this small rise is not lost to cancellation
against ``W_c`` when ``e*`` is small."""
NOT_COMPRESSED = Compression(False, math.nan, math.nan, math.nan, math.nan)


@njit(inline="always")
def _compressed(state, e2):
    """The ``Compression`` of compression ending at ``state`` (``e2 = e*^2``)."""
    return Compression(True, state.imp, state.wn, (1.0 - e2) * state.wn, -e2 * state.wn)

Accuracy = namedtuple("Accuracy", ["steps", "tolerance", "max_steps"])
Accuracy.__doc__ = """Accuracy settings of ``solve_contact`` (see its parameters)."""
DEFAULT_ACCURACY = Accuracy(DEFAULT_STEPS, DEFAULT_TOLERANCE, DEFAULT_MAX_STEPS)

ContactResult = namedtuple("ContactResult", [
    "status", "end_state", "p1", "p2", "i_f", "i_s", "i_c", "w_c", "w_n", "w_fr",
    "w_n_stick", "rk4_steps"])
ContactResult.__doc__ = """Result of ``solve_contact`` (see its Returns)."""


@njit(inline="always")
def velocity(c, p1, p2, imp):
    """Relative contact velocity (m/s, contact frame) after the tangential impulse
    ``(p1, p2)`` and the normal impulse ``imp`` (kg m/s): ``v0 + K P``."""
    v1 = c.v01 + c.k11 * p1 + c.k12 * p2 + c.k13 * imp
    v2 = c.v02 + c.k12 * p1 + c.k22 * p2 + c.k23 * imp
    vn = c.v0n + c.k13 * p1 + c.k23 * p2 + c.k33 * imp
    return v1, v2, vn


@njit(inline="always")
def slip_point(c, state):
    """The slip direction, its rates and the slip speed at ``state`` (``SlipPoint``)."""
    v1, v2, vn = velocity(c, state.p1, state.p2, state.imp)
    s = math.sqrt(v1 * v1 + v2 * v2)
    inv_s = 1.0 / s
    u1 = v1 * inv_s
    u2 = v2 * inv_s
    g1 = c.k13 - c.mu * (c.k11 * u1 + c.k12 * u2)  # d v_t / dI
    g2 = c.k23 - c.mu * (c.k12 * u1 + c.k22 * u2)
    dvn = c.k33 - c.mu * (c.k13 * u1 + c.k23 * u2)  # d v_n / dI
    sigma = u1 * g1 + u2 * g2  # d|v_t|/dI
    return SlipPoint(vn, s, u1, u2, g1, g2, dvn, sigma)


@njit(inline="always")
def linear_slip(c, state, pt, h):
    """Slip at the constant rates of ``pt`` for the impulse ``h`` (kg m/s): exact while
    ``v_t`` falls linearly to zero (the landing)."""
    return SlipState(state.imp + h, state.p1 - c.mu * pt.u1 * h, state.p2 - c.mu * pt.u2 * h,
                     state.wn + h * (pt.vn + 0.5 * pt.dvn * h),
                     state.wfr - c.mu * h * (pt.s - 0.5 * (-pt.sigma) * h))


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


@njit(inline="always")
def slip_state(c, w1, w2, imp, wfr, wn):
    """The ``SlipState`` with slip velocity ``(w1, w2)`` (m/s) at the normal impulse
    ``imp``, with the works ``wfr``, ``wn`` so far (J): ``P_t`` from
    ``v_t = v_t0 + K_tt P_t + K_tn I``."""
    r1 = w1 - c.v01 - c.k13 * imp
    r2 = w2 - c.v02 - c.k23 * imp
    inv_det = 1.0 / (c.k11 * c.k22 - c.k12 * c.k12)
    p1 = (c.k22 * r1 - c.k12 * r2) * inv_det
    p2 = (c.k11 * r2 - c.k12 * r1) * inv_det
    return SlipState(imp, p1, p2, wn, wfr)


@njit(inline="always")
def normal_work(c, a, b, step):
    """``W_n(b) - W_n(a)`` over the ``tau`` step ``step`` from the state ``a`` to ``b`` (J).

    ``v_n = v0n + K_nt . P_t + K_33 I`` and ``P_t = K_tt^-1 (v_t - v_t0 - K_tn I)``, so
    ``int v_n dI`` needs only ``int v_t dI`` (the step's ``q``, an exponential-weighted
    quadrature like ``W_fr``'s) besides closed forms. ``W_n`` is integrated on its own, not
    taken from the total work: when the normal work is a tiny part of the friction work
    (grazing contacts) the latter's integration error would swamp it.
    """
    d = b.imp - a.imp
    mean = 0.5 * (a.imp + b.imp)
    # int (v_t - v_t0 - K_tn I) dI, then K_tt^-1 of it: int P_t dI.
    r1 = step.q1 - c.v01 * d - c.k13 * mean * d
    r2 = step.q2 - c.v02 * d - c.k23 * mean * d
    inv_det = 1.0 / (c.k11 * c.k22 - c.k12 * c.k12)
    pi1 = (c.k22 * r1 - c.k12 * r2) * inv_det
    pi2 = (c.k11 * r2 - c.k12 * r1) * inv_det
    return (c.v0n + c.k33 * mean) * d + c.k13 * pi1 + c.k23 * pi2


@njit(inline="always")
def _event_value(c, w1, w2, state, kind, target, rise_left):
    """``g`` and ``dg/dtau`` of the event ``kind`` at ``state`` (slip velocity ``w``):
    ``v_n`` (kind 0), ``-rise_left``, the normal work since compression less the rise to
    the separation (kind 1), or ``I - target`` (2)."""
    s = math.sqrt(w1 * w1 + w2 * w2)  # dI/dtau
    if kind == 0:
        dvn = c.k33 - c.mu * (c.k13 * w1 + c.k23 * w2) / s
        return velocity(c, state.p1, state.p2, state.imp)[2], dvn * s
    if kind == 1:
        return -rise_left, velocity(c, state.p1, state.p2, state.imp)[2] * s
    return state.imp - target, s


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
def locate_in_step(c, start, w1, w2, lam, h, kind, target, rise_left, end, tol_imp):
    """The point inside the ``tau`` step ``h`` from ``start`` (a ``SlipState`` with
    slip velocity ``w``) to ``end`` (a ``mcbat.core.cabo2012.slip_time.TauStep``)
    where the event ``kind`` (see ``_event_value``; ``rise_left`` the normal work still
    to rise to the separation at ``start``) goes from ``g < 0`` to ``g >= 0``.

    The cubic Hermite interpolant of ``g`` over the step gives the first guess; Newton's
    method on partial Lawson steps (each as accurate as a whole one), safeguarded by the
    bracket, polishes it to ``tol_imp`` in impulse. Returns ``(step, state, dW_n)`` there,
    ``dW_n`` the normal work from ``start``.
    """
    g0, d0 = _event_value(c, w1, w2, start, kind, target, rise_left)
    stop = slip_state(c, end.w1, end.w2, end.imp, end.wfr, 0.0)
    dwn = normal_work(c, start, stop, end)
    g1, d1 = _event_value(c, end.w1, end.w2, stop, kind, target, rise_left - dwn)
    lo = 0.0
    hi = 1.0
    theta = _hermite_root(g0, g1, d0 * h, d1 * h)
    trial, state = end, stop
    for _ in range(EVENT_MAX_ITER):
        trial = tau_step(c, w1, w2, start.imp, start.wfr, lam, theta * h)
        state = slip_state(c, trial.w1, trial.w2, trial.imp, trial.wfr, 0.0)
        dwn = normal_work(c, start, state, trial)
        g, dg = _event_value(c, trial.w1, trial.w2, state, kind, target, rise_left - dwn)
        if g == 0.0:
            break
        if g < 0.0:
            lo = theta
        else:
            hi = theta
        new = theta - g / (dg * h) if dg != 0.0 else -1.0
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        # Impulse moved by the update: dI/dtau = |v_t| at the trial.
        moved = abs(new - theta) * h * math.sqrt(trial.w1 * trial.w1 + trial.w2 * trial.w2)
        theta = new
        if moved <= tol_imp:
            break
    return trial, SlipState(state.imp, state.p1, state.p2, start.wn + dwn, state.wfr), dwn


@njit(inline="always")
def impulse_step_cap(s, lam, impulse):
    """The ``tau`` step over which the normal impulse grows by ``impulse`` (kg m/s) at the
    slip speed ``s e^(-lam tau)`` (inf if it never does)."""
    x = lam * impulse / s
    if x >= 1.0:
        return math.inf
    if abs(x) < 1e-8:
        return impulse / s
    return -math.log1p(-x) / lam


@njit(inline="always")
def _may_land(pt, allowed):
    """Whether landing from ``pt`` (``rate < 0``) errs by at most ``allowed`` (kg m/s):
    linear in ``I``, the rest ``d = |v_t| / (-rate)`` is right but for the change of
    ``rate`` with the turn the direction has left, ``|turn| / relax`` (linearised), so the
    error is ``d min(1, |rate_slope turn / (relax rate)|)``. Written without divisions: it
    is asked at every step."""
    fall = -pt.rate  # > 0
    if not pt.relax > 0.0:
        return pt.s <= allowed * fall
    change = abs(pt.rate_slope * pt.turn)
    spread = pt.relax * fall
    if change >= spread:
        return pt.s <= allowed * fall
    return pt.s * change <= allowed * fall * spread


@njit(inline="always")
def _land(c, state, comp, e2, rise_left):
    """The last sliver of slip, ``v_t`` falling linearly to zero, with the events in it in
    closed form (``v_n`` is linear and ``W_n`` quadratic in ``I`` there); ``rise_left`` is
    the normal work still to rise to the separation (J, after compression).

    Returns ``(state, compression, separated, rise_left)``.
    """
    pt = slip_point(c, state)
    if not (pt.s > 0.0 and pt.sigma < 0.0):  # stopped exactly (or too little to tell)
        return remove_residual_slip(c, state), comp, False, rise_left
    h = pt.s / (-pt.sigma)  # impulse left until v_t = 0
    if not comp.done and pt.vn + pt.dvn * h >= 0.0:
        state = linear_slip(c, state, pt, -pt.vn / pt.dvn)
        comp = _compressed(state, e2)
        rise_left = comp.rise
        if e2 == 0.0:
            return state, comp, True, 0.0  # e* = 0: separation at once
        pt = slip_point(c, state)
        h = pt.s / (-pt.sigma)
    if comp.done:
        gain = h * (pt.vn + 0.5 * pt.dvn * h)  # W_n gained over the landing
        if gain >= rise_left:
            # Solve vn x + dvn x^2 / 2 = rise_left.
            root = math.sqrt(max(pt.vn * pt.vn + 2.0 * pt.dvn * rise_left, 0.0))
            x = (2.0 * rise_left) / (pt.vn + root) if pt.vn + root > 0.0 else h
            return linear_slip(c, state, pt, x), comp, True, 0.0
        rise_left -= gain
    return remove_residual_slip(c, linear_slip(c, state, pt, h)), comp, False, rise_left


SlipControl = namedtuple("SlipControl", ["tolerance", "v_scale", "i_scale", "impulse_max",
                                         "s_stop", "s_resolution"])
SlipControl.__doc__ = """The slip step rule's scales: ``tolerance``, ``|v0|`` (m/s), ``I_scale``
and the largest impulse of one step (kg m/s), the slip speed taken as zero and the one
below which a minimum of the slip speed is a stop (m/s)."""


@njit(inline="always")
def slip_control(c, tolerance, impulse_max_per_scale):
    """``SlipControl`` of contact ``c``; a step takes at most ``I_scale`` times
    ``impulse_max_per_scale`` of impulse."""
    v_scale = math.sqrt(c.v01 * c.v01 + c.v02 * c.v02 + c.v0n * c.v0n)
    i_scale = 2.0 * (-c.v0n) / c.k33  # frictionless, fully elastic impact impulse
    return SlipControl(tolerance, v_scale, i_scale, i_scale * impulse_max_per_scale,
                       STICK_TOLERANCE * v_scale, SLIP_RESOLUTION * v_scale)


@njit(inline="always")
def step_plan(ctl, pt, imp, h, first):
    """The slip step rule, shared by ``solve_contact`` and ``contact_history``: at the
    slip ``pt`` and normal impulse ``imp``, with ``h`` the step the last one proposed.

    Returns ``(action, h, stick_rate, tol_i)``: action ``STEP_ACTION`` (a step of
    ``h``), ``LAND_ACTION`` or ``STOP_ACTION`` (the slip speed is at most
    ``SLIP_RESOLUTION |v0|`` at incidence, or there and not falling: slip has stopped, or
    passed a minimum that close to zero); the rate (1/kg)
    at which a slip error moves ``I_s`` and the impulse error allowed (kg m/s), for
    ``error_ratio``.
    """
    lam = -pt.rate
    # Impulse errors are relative to I_scale, or to the stick impulse where sliding is
    # predicted to stop before it (I_s is reported to a relative accuracy).
    stick_rate = max(lam, pt.s / ctl.i_scale)
    tol_i = ctl.tolerance * min(ctl.i_scale, imp + pt.s / stick_rate)
    if pt.s <= ctl.s_resolution and (first or not lam > 0.0):  # see SLIP_RESOLUTION
        return STOP_ACTION, h, stick_rate, tol_i
    if lam > 0.0 and (pt.s <= ctl.s_stop or _may_land(pt, LANDING_FRACTION * tol_i)):
        return LAND_ACTION, h, stick_rate, tol_i
    if first:
        # A first guess from the rates the step must follow: the speed's (lam) and the
        # direction's turn; the error control corrects it from there.
        h = 2.0 / max(abs(lam), abs(pt.turn), 1e-300)
    h = min(h, STABLE_STEP / pt.stiffness)
    if not (lam >= 0.0 and pt.s * h <= ctl.impulse_max):  # else the cap cannot bind
        h = min(h, impulse_step_cap(pt.s, lam, ctl.impulse_max))
    return STEP_ACTION, h, stick_rate, tol_i


@njit(inline="always")
def error_ratio(ctl, step, stick_rate, tol_i):
    """The step's measured error over what is allowed (accept if <= 1): in the slip
    velocity, the impulse, the friction work, and the shift of the stick point (a slip
    velocity error over the rate the slip speed falls at: the dominant error of ``I_s``
    in creeping slip)."""
    tol_v = ctl.tolerance * ctl.v_scale
    return max(step.error_v / tol_v, step.error_i / tol_i,
               step.error_w / (tol_v * ctl.i_scale), step.error_v / stick_rate / tol_i)


@njit(inline="always")
def next_step(h, ratio, last_h, last_ratio):
    """The step after an accepted one of length ``h`` and error ``ratio``, the accepted step
    before it ``last_h`` with error ``last_ratio`` (``last_h = 0`` if a rejection came in
    between, or at the start): Gustafsson's predictive controller,
    ``0.9 (h / last_h) (last_ratio / ratio^2)^(1/4)``, between a fifth and five times ``h``.

    It extrapolates the trend of the error along the slip. Where the slip direction
    settles, the error per step falls fast and the plain rule (``resized_step``) trails
    behind it, so that the steps follow their own history more than the error, and the step
    sequence does not scale uniformly with the tolerance (whence errors that change sign
    between tolerances). After a rejection the plain rule is used. (K. Gustafsson, ACM
    TOMS 20, 496-517, 1994; Hairer & Wanner, Solving ODEs II, Sec. IV.8.)
    """
    if not (last_h > 0.0 and ratio > 0.0 and last_ratio > 0.0):
        return resized_step(h, ratio)
    factor = 0.9 * (h / last_h) * math.sqrt(math.sqrt(last_ratio / (ratio * ratio)))
    return h * min(5.0, max(0.2, factor))


@njit(inline="always")
def resized_step(h, ratio):
    """The next step after one with error ``ratio``: ``0.9 ratio^(-1/4)`` (the estimate is
    of 4th order in ``h``), between a fifth and five times ``h``."""
    if not ratio > 0.0:
        return 5.0 * h
    factor = 0.9 / math.sqrt(math.sqrt(ratio))
    return h * (max(0.2, factor) if ratio > 1.0 else min(5.0, factor))


@njit
def _slip_phase(c, acc, e2):
    """Slip from incidence until ``v_t = 0`` or separation: Lawson RK4 in ``tau``
    (``mcbat.core.cabo2012.slip_time``) with a-posteriori step control, the compression
    and separation events, and the landing on ``v_t = 0``.

    Returns ``(status, state, compression, separated, steps, rise_left)``; ``steps``
    counts every step tried, rejected ones included; ``rise_left`` is the normal work
    still to rise to the separation (J, once compression has ended).
    """
    ctl = slip_control(c, acc.tolerance, 1.0 / acc.steps)
    event_tolerance = EVENT_TOLERANCE * ctl.i_scale
    w1, w2 = c.v01, c.v02
    state = SlipState(0.0, 0.0, 0.0, 0.0, 0.0)
    comp = NOT_COMPRESSED
    rise_left = math.nan  # after compression: the normal work still to rise to separation
    h = math.inf
    last_h = 0.0  # the last accepted step and its error ratio (0: none, or a rejection since)
    last_ratio = 0.0
    steps = 0
    while steps < acc.max_steps:
        pt = tau_point(c, w1, w2)
        action, h, stick_rate, tol_i = step_plan(ctl, pt, state.imp, h, steps == 0)
        if action == STOP_ACTION:
            return st.OK, remove_residual_slip(c, state), comp, False, steps, rise_left
        if action == LAND_ACTION:
            end, comp, separated, rise_left = _land(c, state, comp, e2, rise_left)
            return st.OK, end, comp, separated, steps, rise_left
        lam = -pt.rate
        step = tau_step(c, w1, w2, state.imp, state.wfr, lam, h)
        steps += 1
        ratio = error_ratio(ctl, step, stick_rate, tol_i)
        if ratio > 1.0:  # rejected: retry shorter
            h = resized_step(h, ratio)
            last_h = 0.0
            continue
        new = slip_state(c, step.w1, step.w2, step.imp, step.wfr, 0.0)
        dwn = normal_work(c, state, new, step)
        new = SlipState(new.imp, new.p1, new.p2, state.wn + dwn, new.wfr)
        if not comp.done and velocity(c, new.p1, new.p2, new.imp)[2] >= 0.0:
            # (np.int64: a constant would compile locate_in_step once per event kind)
            step, new, dwn = locate_in_step(c, state, w1, w2, lam, h, np.int64(0), 0.0, 0.0,
                                            step, event_tolerance)
            comp = _compressed(new, e2)
            rise_left = comp.rise
            if e2 == 0.0:
                return st.OK, new, comp, True, steps, 0.0  # e* = 0: separation at once
        elif comp.done and dwn >= rise_left:
            step, new, dwn = locate_in_step(c, state, w1, w2, lam, h, np.int64(1), 0.0,
                                            rise_left, step, event_tolerance)
            return st.OK, new, comp, True, steps, 0.0
        else:
            if comp.done:
                rise_left -= dwn
            h, last_h, last_ratio = next_step(h, ratio, last_h, last_ratio), h, ratio
        state = new
        w1, w2 = step.w1, step.w2
    return st.MAX_STEPS, state, comp, True, steps, rise_left


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
def _linear_phase(c, state, comp, d1, d2, e, rise_left):
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
        comp = Compression(True, i_c, w_c, (1.0 - e * e) * w_c, -(e * e) * w_c)
        dh = (i_c - state.imp) + math.sqrt(2.0 * (e * e) * (-w_c) / slope)
    else:
        gap = rise_left  # >= 0 while still in contact
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
    """The one place a failed ``ContactResult`` is built: every output NaN."""
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
        Slip steps take at most ``I_scale / steps`` of impulse, ``I_scale = 2 |v0n| / K_33``.
    tolerance : float
        Local error allowed per slip step, relative to ``|v0|`` (slip velocity),
        ``I_scale`` (impulse) and ``|v0| I_scale`` (friction work); in (0, 1). The accuracy
        knob: errors scale with it, the step count with its -1/4 power.
    max_steps : int
        Bound on slip steps (rejected ones included); reaching it returns ``MAX_STEPS``.

    Returns
    -------
    ContactResult
        ``(status, end_state, p1, p2, i_f, i_s, i_c, w_c, w_n, w_fr, w_n_stick,
        rk4_steps)``: tangential impulses ``P1, P2`` and normal impulse ``I_f`` (kg m/s) at
        separation; the stick impulse ``I_s`` (NaN if sliding never stopped; 0 for
        incidence with ``|v_t| <= SLIP_RESOLUTION |v0|``); the end of compression ``I_c``
        and ``W_c = W_n(I_c)``; the normal and friction work at separation (J);
        ``W_n(I_s)`` (the paper's ``C = -W_n(I_s)``); and the number of slip steps tried
        (Lawson RK4 steps). On a failure status every physical output is NaN
        (``failed_contact``).
    """
    c = Contact(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu)
    acc = Accuracy(steps, tolerance, max_steps)
    if not _valid_contact(c, e, acc):
        return failed_contact(st.INVALID_INPUT)
    if not (v0n < 0.0):
        return failed_contact(st.NOT_APPROACHING)
    s_stop = STICK_TOLERANCE * math.sqrt(v01 * v01 + v02 * v02 + v0n * v0n)
    state = SlipState(0.0, 0.0, 0.0, 0.0, 0.0)
    comp = NOT_COMPRESSED
    rise_left = math.nan
    n_rk4 = 0
    if mu > 0.0 and math.sqrt(v01 * v01 + v02 * v02) > s_stop:
        code, state, comp, separated, n_rk4, rise_left = _slip_phase(c, acc, e * e)
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
    ok, state, comp, slip = _linear_phase(c, state, comp, d1, d2, e, rise_left)
    if not ok:
        return failed_contact(st.DEGENERATE)
    if mu == 0.0:
        # Without friction v_t still drifts through K_tn; report what it ends at.
        if math.sqrt(slip[0] * slip[0] + slip[1] * slip[1]) <= s_stop:
            end_state = st.STUCK
    return ContactResult(st.OK, end_state, state.p1, state.p2, state.imp, i_s, comp.i_c,
                         comp.w_c, state.wn, state.wfr, wn_s, n_rk4)
