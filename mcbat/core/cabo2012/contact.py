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

from mcbat.core import status as st
from mcbat.core.jit import njit

__all__ = ["reslip_direction", "rk4_step", "slip_velocity",
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


@njit(inline="always")
def slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp):
    """Relative contact velocity (m/s, contact frame) after the tangential impulse
    ``(p1, p2)`` and the normal impulse ``imp`` (kg m/s): ``v0 + K P``."""
    v1 = v01 + k11 * p1 + k12 * p2 + k13 * imp
    v2 = v02 + k12 * p1 + k22 * p2 + k23 * imp
    vn = v0n + k13 * p1 + k23 * p2 + k33 * imp
    return v1, v2, vn


@njit(inline="always")
def _slip_rhs(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, p1, p2, imp):
    """Slip rates ``d(P1, P2, W_n, W_fr)/dI``."""
    v1, v2, vn = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp)
    s = math.sqrt(v1 * v1 + v2 * v2)
    c = mu / s
    return -c * v1, -c * v2, vn, -mu * s


@njit(inline="always")
def _remaining_impulse(vn, dvn, wn, compressed, target, retained):
    """Impulse left until separation if ``v_n`` kept growing at the rate ``dvn`` (kg m/s)."""
    if not (dvn > 0.0):
        return math.inf
    if not compressed:
        w_c = wn - 0.5 * vn * vn / dvn
        target = retained * w_c
    gap = max(target - wn, 0.0)
    return (-vn + math.sqrt(max(vn * vn + 2.0 * dvn * gap, 0.0))) / dvn


@njit(inline="always")
def rk4_step(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, imp, p1, p2, wn, wfr, h,
              a1, a2, a3, a4):
    """One classical RK4 step of the slip ODE from ``imp`` to ``imp + h``.

    ``a1..a4`` are the rates at the start (the first stage), which the caller already has.
    """
    hh = 0.5 * h
    b1, b2, b3, b4 = _slip_rhs(
        k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, p1 + hh * a1, p2 + hh * a2, imp + hh
    )
    c1, c2, c3, c4 = _slip_rhs(
        k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, p1 + hh * b1, p2 + hh * b2, imp + hh
    )
    d1, d2, d3, d4 = _slip_rhs(
        k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, p1 + h * c1, p2 + h * c2, imp + h
    )
    w = h / 6.0
    return (
        imp + h,
        p1 + w * (a1 + 2.0 * (b1 + c1) + d1),
        p2 + w * (a2 + 2.0 * (b2 + c2) + d2),
        wn + w * (a3 + 2.0 * (b3 + c3) + d3),
        wfr + w * (a4 + 2.0 * (b4 + c4) + d4),
    )


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
def _locate_event(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                  imp, p1, p2, wn, wfr, h, kind, target, g0, g1, d0, d1, tol_imp):
    """Locate an event inside the RK4 step ``[imp, imp + h]``.

    ``kind`` 0: end of compression, ``g = v_n``; 1: separation, ``g = W_n - target``.
    ``g0 < 0 <= g1`` at the ends, ``d0, d1`` their derivatives in ``I``. The cubic Hermite
    interpolant of ``g`` (4th-order accurate, like the step) gives the first guess; Newton's
    method on the RK4 solution itself (partial steps from ``imp``) then polishes it to
    ``tol_imp`` in impulse, safeguarded by bisection. Returns the state at the event.
    """
    lo = 0.0
    hi = 1.0
    theta = _hermite_root(g0, g1, d0 * h, d1 * h)
    a1, a2, a3, a4 = _slip_rhs(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, p1, p2, imp)
    out = (imp + h, p1, p2, wn, wfr)
    for _ in range(EVENT_MAX_ITER):
        out = rk4_step(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                        imp, p1, p2, wn, wfr, theta * h, a1, a2, a3, a4)
        v1, v2, vn = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n,
                               out[1], out[2], out[0])
        if kind == 0:
            q1, q2, q3, q4 = _slip_rhs(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                                       out[1], out[2], out[0])
            g = vn
            dg = (k13 * q1 + k23 * q2 + k33) * h
        else:
            g = out[3] - target
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
            out = rk4_step(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                            imp, p1, p2, wn, wfr, theta * h, a1, a2, a3, a4)
            break
    return out


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
    for i in range(RESLIP_SAMPLES):
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
    tuple
        ``(status, end_state, P1, P2, I_f, I_s, I_c, W_c, W_n, W_fr, W_n_at_stick, n_rk4)``:
        tangential impulses ``P1, P2`` and normal impulse ``I_f`` (kg m/s) at separation;
        the stick impulse ``I_s`` (NaN if sliding never stopped; 0 for incidence with
        ``v_t = 0``); the end of compression ``I_c`` and ``W_c = W_n(I_c)``; the normal and
        friction work at separation (J); ``W_n(I_s)`` (the paper's ``C = -W_n(I_s)``); and
        the number of RK4 steps taken.
    """
    nan = math.nan
    if not (math.isfinite(k11) and math.isfinite(k12) and math.isfinite(k13)
            and math.isfinite(k22) and math.isfinite(k23) and math.isfinite(k33)
            and math.isfinite(v01) and math.isfinite(v02) and math.isfinite(v0n)
            and math.isfinite(mu) and math.isfinite(e)
            and mu >= 0.0 and 0.0 <= e <= 1.0 and k33 > 0.0
            and k11 * k22 - k12 * k12 > 0.0 and steps >= 1
            and 0.0 < tolerance < 1.0):
        return (st.INVALID_INPUT, st.SLIDING, nan, nan, nan, nan, nan, nan, nan, nan, nan, 0)
    if not (v0n < 0.0):
        return (st.NOT_APPROACHING, st.SLIDING, nan, nan, nan, nan, nan, nan, nan, nan, nan, 0)

    retained = 1.0 - e * e  # W_n(I_f) = retained * W_c
    v_scale = math.sqrt(v01 * v01 + v02 * v02 + v0n * v0n)
    s_stop = STICK_TOLERANCE * v_scale
    i_scale = 2.0 * (-v0n) / k33  # frictionless, fully elastic impact impulse
    h_max = i_scale / steps
    error_per_step = tolerance * i_scale  # impulse error allowed per slip step, kg m/s
    event_tolerance = EVENT_TOLERANCE * i_scale

    imp = 0.0
    p1 = 0.0
    p2 = 0.0
    wn = 0.0
    wfr = 0.0
    compressed = False
    i_c = nan
    w_c = nan
    target = nan
    i_s = nan
    wn_s = nan
    n_rk4 = 0

    s0 = math.sqrt(v01 * v01 + v02 * v02)
    sliding = mu > 0.0 and s0 > s_stop

    inv_mu_ktt = inverse_slip_stiffness(k11, k12, k22, mu)
    approach = False  # set once sliding is predicted to stop well before separation
    # The relaxed budget on the way into a stick needs a stick that holds with margin: near
    # |f| = mu the outcome (stick or re-slip) depends on exactly how slip dies out.
    f1, f2 = stick_impulse_rate(k11, k12, k13, k22, k23)
    robust_stick = f1 * f1 + f2 * f2 <= (ROBUST_STICK * mu) ** 2
    # ---- slip phase: fixed-step RK4 in I with zero-slip detection ----
    n_iter = 0  # every pass, RK4 or not: the loop is bounded whatever happens
    while sliding:
        n_iter += 1
        if n_rk4 >= max_steps or n_iter > max_steps + 8:
            return (st.MAX_STEPS, st.SLIDING, p1, p2, imp, i_s, i_c, w_c, wn, wfr, wn_s, n_rk4)
        v1, v2, vn = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp)
        s = math.sqrt(v1 * v1 + v2 * v2)
        inv_s = 1.0 / s
        u1 = v1 * inv_s
        u2 = v2 * inv_s
        g1 = k13 - mu * (k11 * u1 + k12 * u2)  # d v_t / dI
        g2 = k23 - mu * (k12 * u1 + k22 * u2)
        dvn = k33 - mu * (k13 * u1 + k23 * u2)  # d v_n / dI
        sigma = u1 * g1 + u2 * g2  # d|v_t|/dI
        omega = abs(u1 * g2 - u2 * g1) * inv_s  # |du/dI|: how fast the slip direction turns
        h = h_max
        land = False
        budget = error_per_step
        if sigma < 0.0:
            dist = s / (-sigma)  # predicted impulse left until v_t = 0
            length = dist
            if not approach and robust_stick:
                approach = dist < APPROACH_MARGIN * _remaining_impulse(
                    vn, dvn, wn, compressed, target, retained)
            if approach:
                # Sliding will stop well before separation. After stick the constraint
                # v_t = 0 fixes the tangential impulse from I alone, so errors made on the way
                # in are mostly forgotten: a looser budget costs no accuracy in the result.
                budget = APPROACH_FACTOR * error_per_step
            if s <= s_stop or mu * omega * dist * dist <= LANDING_FRACTION * error_per_step:
                # The direction has settled: v_t falls linearly to zero. Assuming so costs
                # about mu * (turn left ~ omega * dist) * dist of impulse.
                h = dist
                land = True
            else:
                h = min(h, MAX_SLIP_FRACTION * dist)  # no RK4 stage may pass v_t = 0
        else:
            length = s / math.sqrt(g1 * g1 + g2 * g2)  # impulse over which v_t changes by |v_t|
        if not land:
            # The slip direction relaxes at the rate ~ mu K_tt / |v_t| (the Jacobian of the
            # slip ODE): a longer step is unstable and can freeze a spurious sliding mode
            # near v_t = 0.
            h = min(h, MAX_SLIP_FRACTION * s * inv_mu_ktt)
        if not land and omega > 0.0:
            # RK4 local error ~ mu * omega * h^5 / length^3 (the turning slip direction is the
            # only nonlinearity); keep it below the budget.
            h = min(h, (budget * length ** 3 / (mu * omega)) ** 0.2)

        if land:
            n_imp = imp + h
            n_p1 = p1 - mu * u1 * h
            n_p2 = p2 - mu * u2 * h
            n_wn = wn + h * (vn + 0.5 * dvn * h)
            n_wfr = wfr - 0.5 * mu * s * h
        else:
            n_imp, n_p1, n_p2, n_wn, n_wfr = rk4_step(
                k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu, imp, p1, p2, wn, wfr, h,
                -mu * u1, -mu * u2, vn, -mu * s)
            n_rk4 += 1
        n_vn = v0n + k13 * n_p1 + k23 * n_p2 + k33 * n_imp

        if not compressed and n_vn >= 0.0:
            if land:
                # Linear in I on this step: the crossing is explicit.
                frac = -vn / (n_vn - vn)
                h = frac * h
                n_imp = imp + h
                n_p1 = p1 - mu * u1 * h
                n_p2 = p2 - mu * u2 * h
                n_wn = wn + h * (vn + 0.5 * dvn * h)
                n_wfr = wfr - mu * h * (s - 0.5 * (-sigma) * h)
                land = False
            else:
                e1, e2, e3, e4 = _slip_rhs(k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                                           n_p1, n_p2, n_imp)
                n_imp, n_p1, n_p2, n_wn, n_wfr = _locate_event(
                    k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                    imp, p1, p2, wn, wfr, h, 0, 0.0, vn, n_vn, dvn,
                    k13 * e1 + k23 * e2 + k33, event_tolerance)
            compressed = True
            i_c = n_imp
            w_c = n_wn
            target = retained * w_c
            imp, p1, p2, wn, wfr = n_imp, n_p1, n_p2, n_wn, n_wfr
            if retained == 1.0:
                # e* = 0: the bodies separate at the end of compression.
                return (st.OK, st.SLIDING, p1, p2, imp, i_s, i_c, w_c, wn, wfr, wn_s, n_rk4)
            continue

        if compressed and n_wn >= target:
            if land:
                # W_n is quadratic in I on this step.
                a = 0.5 * dvn
                c = wn - target
                disc = vn * vn - 4.0 * a * c
                root = math.sqrt(max(disc, 0.0))
                h = (2.0 * (-c)) / (vn + root) if vn + root > 0.0 else h
                n_imp = imp + h
                n_p1 = p1 - mu * u1 * h
                n_p2 = p2 - mu * u2 * h
                n_wn = wn + h * (vn + 0.5 * dvn * h)
                n_wfr = wfr - mu * h * (s - 0.5 * (-sigma) * h)
            else:
                n_imp, n_p1, n_p2, n_wn, n_wfr = _locate_event(
                    k11, k12, k13, k22, k23, k33, v01, v02, v0n, mu,
                    imp, p1, p2, wn, wfr, h, 1, target, wn - target, n_wn - target, vn, n_vn,
                    event_tolerance)
            return (st.OK, st.SLIDING, n_p1, n_p2, n_imp, i_s, i_c, w_c, n_wn, n_wfr, wn_s,
                    n_rk4)

        imp, p1, p2, wn, wfr = n_imp, n_p1, n_p2, n_wn, n_wfr
        if land:
            sliding = False
            # The landing bounds the impulse error; K_tt turns it into a residual slip that
            # the stick phase would carry to the end (and let friction work on it). Remove
            # it: the tangential impulse that makes v_t = 0 exactly at I_s.
            r1, r2, _ = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp)
            det = k11 * k22 - k12 * k12
            if det > 0.0:
                q1 = (k22 * r1 - k12 * r2) / det
                q2 = (k11 * r2 - k12 * r1) / det
                p1 -= q1
                p2 -= q2
                wfr -= 0.5 * (r1 * q1 + r2 * q2)  # the kinetic energy this takes out

    # ---- sliding has stopped (or never started): stick, re-slip, or frictionless ----
    if mu > 0.0:
        i_s = imp
        wn_s = wn
        f1, f2 = stick_impulse_rate(k11, k12, k13, k22, k23)
        if f1 * f1 + f2 * f2 <= mu * mu:
            end_state = st.STUCK
            d1 = f1
            d2 = f2
        else:
            u1, u2, lam = reslip_direction(k11, k12, k13, k22, k23, mu)
            if lam <= 0.0:
                return (st.DEGENERATE, st.SLIDING, p1, p2, imp, i_s, i_c, w_c, wn, wfr, wn_s,
                        n_rk4)
            end_state = st.SLIDING
            d1 = -mu * u1
            d2 = -mu * u2
    else:
        end_state = st.SLIDING  # settled from the final v_t below
        d1 = 0.0
        d2 = 0.0

    # ---- linear phase: dP/dI = (d1, d2, 1) exactly, so W_n is quadratic in I ----
    v1, v2, vn = slip_velocity(k11, k12, k13, k22, k23, k33, v01, v02, v0n, p1, p2, imp)
    slope = k13 * d1 + k23 * d2 + k33  # d v_n / dI
    if not (slope > 0.0):
        return (st.DEGENERATE, end_state, p1, p2, imp, i_s, i_c, w_c, wn, wfr, wn_s, n_rk4)
    c1 = k11 * d1 + k12 * d2 + k13  # d v_t / dI
    c2 = k12 * d1 + k22 * d2 + k23
    if not compressed:
        # Compression ends in this phase; W_n = W_c + slope/2 (I - I_c)^2 about the vertex.
        i_c = imp - vn / slope
        w_c = wn - 0.5 * vn * vn / slope
        target = retained * w_c
        dh = (i_c - imp) + math.sqrt(2.0 * (e * e) * (-w_c) / slope)
    else:
        gap = target - wn  # >= 0 while still in contact
        if gap <= 0.0:
            dh = 0.0
        else:
            dh = 2.0 * gap / (vn + math.sqrt(vn * vn + 2.0 * slope * gap))
    p1 += d1 * dh
    p2 += d2 * dh
    wn += dh * (vn + 0.5 * slope * dh)
    wfr += dh * (v1 * d1 + v2 * d2) + 0.5 * dh * dh * (c1 * d1 + c2 * d2)
    imp += dh
    if mu == 0.0:
        # Without friction v_t still drifts through K_tn; report what it ends at.
        f1 = v1 + c1 * dh
        f2 = v2 + c2 * dh
        end_state = st.STUCK if math.sqrt(f1 * f1 + f2 * f2) <= s_stop else st.SLIDING
    return (st.OK, end_state, p1, p2, imp, i_s, i_c, w_c, wn, wfr, wn_s, n_rk4)
