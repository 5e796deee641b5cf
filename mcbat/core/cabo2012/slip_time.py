"""The slip phase in the slip-scaled time ``tau`` (``dI = |v_t| dtau``), by Lawson RK4.

Why ``tau``
-----------
In the normal impulse ``I`` the slip ODE ``dv_t/dI = K_tn - mu K_tt u`` (``u = v_t/|v_t|``)
is singular where sliding stops: the slip direction keeps turning as ``|v_t| -> 0`` (it
relaxes towards its fixed direction much more slowly than the speed falls), so the
solution is not smooth in ``I`` at the stick point and no step rule in ``I`` controls the
error of ``I_s``. In ``tau`` the same motion is

    dv_t/dtau = |v_t| K_tn - mu K_tt v_t,    dI/dtau = |v_t|,

a smooth, homogeneous ODE on which stick is reached only as ``tau -> inf``, exponentially.

Lawson's transformation
-----------------------
The fast part of that motion is the exponential change of the slip speed,
``d ln|v_t|/dtau = u . g(u)`` with ``g = K_tn - mu K_tt u`` (the same number as
``d|v_t|/dI``). Each step freezes its rate ``-lam = u . g`` at the step start and
integrates ``z = e^(lam tau) v_t``, whose equation is autonomous (the ODE is homogeneous)

    dz/dtau = F(z) = |z| K_tn - mu K_tt z + lam z,

by classical RK4. ``z`` only turns and changes slowly (exactly constant when the slip
direction is constant, where RK4 in ``I`` was exact too), so the step is limited by how
fast the direction turns, not by the speed's decay. Then ``v_t = e^(-lam h) z``.

Quadratures
-----------
``I`` and the friction work ``W_fr = -mu int |v_t|^2 dtau`` are integrals of
``e^(-lam tau) |z|`` and ``e^(-2 lam tau) |z|^2``. Over a step the smooth factor is its cubic
Hermite interpolant (values and slopes at both ends, 4th order like the step) and the
exponential is integrated exactly (moments ``int_0^1 e^(-a t) t^k dt``); so is
``int v_t dI = int e^(-2 lam tau) z |z| dtau``, from which the caller integrates ``W_n``.
The tangential impulse needs no quadrature: ``v_t = v_t0 + K_tt P_t + K_tn I`` gives it.

Error estimate
--------------
RK4 with the FSAL stage ``F(z_end)`` has an embedded third-order solution
(weights ``1/6, 1/3, 1/3, 0, 1/6``): the difference ``h (F_4 - F_5) / 6`` estimates the local
error of ``z``, measured, not modelled. The step controls it in the three quantities it
reaches: the slip velocity at the end (``e^(-lam h)`` times it), the impulse and the friction
work of the step (it weighted by the exponentials over the step). The quadratures add their
own error: the Hermite interpolants of ``|z|`` and ``|z|^2`` are compared at the step's
middle with the norm of the Hermite interpolant of ``z`` (both 4th order, so their
difference is of the size of the interpolation error, whose shape is ``t^2 (1 - t)^2``), and
the difference, integrated with that shape and the exponential weight, is added to the
impulse's and the friction work's estimates.
"""

import math
from collections import namedtuple

from mcbat.core.jit import njit

__all__ = ["TauPoint", "TauStep", "exp_moments", "tau_point", "tau_step"]

# Below this |a| the moments come from their Taylor series (the recurrence from e^-a loses
# about log10(k! / |a|^k) digits), with fewer terms below SHORT_SERIES_BELOW and 0.03.
SERIES_BELOW = 0.5
SERIES_TERMS = 15  # 0.5^15 / 15! = 2e-17
SHORT_SERIES_BELOW = 0.1
SHORT_SERIES_TERMS = 10  # 0.1^10 / 10! = 3e-17
_INVERSES = tuple(1.0 / n for n in range(1, SERIES_TERMS + 5))  # 1/1, 1/2, ...

TauPoint = namedtuple("TauPoint", ["s", "u1", "u2", "g1", "g2", "rate", "turn", "relax",
                                   "stiffness", "rate_slope"])
TauPoint.__doc__ = """The slip at one state: speed ``s`` (m/s), direction ``u``, the slip
acceleration ``g = dv_t/dI`` (1/kg), ``rate = u . g = d ln|v_t|/dtau = d|v_t|/dI``, and
(all 1/kg) how fast the direction turns, ``turn = u x g = dphi/dtau``; the rate ``relax`` at
which it relaxes towards a fixed direction (> 0 if it does); a bound on the spectral
radius of the Jacobian of ``F`` (the step's stability limit); ``rate_slope = d rate/dphi``."""

TauStep = namedtuple("TauStep", ["w1", "w2", "imp", "wfr", "error_v", "error_i",
                                 "error_w", "q1", "q2"])
TauStep.__doc__ = """The end of one step: slip velocity ``w`` (m/s), normal impulse ``imp``
(kg m/s), friction work ``wfr`` (J), the local error estimates of ``w`` (m/s), of the
step's impulse (kg m/s) and of its friction work (J), and ``q = int v_t dI`` over the step
(J/(kg m/s) units of velocity times impulse), from which ``W_n`` follows."""


@njit(inline="always")
def tau_point(c, w1, w2):
    """``TauPoint`` of the slip velocity ``(w1, w2)`` (m/s, > 0) of contact ``c``."""
    s = math.sqrt(w1 * w1 + w2 * w2)
    inv_s = 1.0 / s
    u1 = w1 * inv_s
    u2 = w2 * inv_s
    g1 = c.k13 - c.mu * (c.k11 * u1 + c.k12 * u2)
    g2 = c.k23 - c.mu * (c.k12 * u1 + c.k22 * u2)
    rate = u1 * g1 + u2 * g2
    turn = u1 * g2 - u2 * g1
    # mu K_tt applied to u_perp = (-u2, u1); the Jacobian of F at z = v_t is, in the basis
    # (u, u_perp), [[0, a], [turn, -relax]] with a = -u . mu K_tt u_perp.
    q1 = c.mu * (c.k12 * u1 - c.k11 * u2)
    q2 = c.mu * (c.k22 * u1 - c.k12 * u2)
    relax = rate + (u1 * q2 - u2 * q1)
    a = -(u1 * q1 + u2 * q2)
    stiffness = abs(relax) + math.sqrt(abs(a * turn))
    return TauPoint(s, u1, u2, g1, g2, rate, turn, relax, stiffness, turn + a)


@njit(inline="always")
def _z_rate(c, lam, z1, z2):
    """``F(z) = |z| K_tn - mu K_tt z + lam z`` (m/s per kg)."""
    return _z_rate_at(c, lam, z1, z2, math.sqrt(z1 * z1 + z2 * z2))


@njit(inline="always")
def _z_rate_at(c, lam, z1, z2, s):
    """``_z_rate`` given ``s = |z|``."""
    f1 = s * c.k13 - c.mu * (c.k11 * z1 + c.k12 * z2) + lam * z1
    f2 = s * c.k23 - c.mu * (c.k12 * z1 + c.k22 * z2) + lam * z2
    return f1, f2


@njit(inline="always")
def _moment_series(a, terms):
    """``m_k = sum_j (-a)^j / (j! (k + j + 1))`` for ``k = 0..3``, its first ``terms``
    terms summed from the smallest (Horner); ``terms`` a constant, so the loop unrolls."""
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    for j in range(terms - 1, -1, -1):
        r = a * _INVERSES[j]
        m0 = _INVERSES[j] - r * m0
        m1 = _INVERSES[j + 1] - r * m1
        m2 = _INVERSES[j + 2] - r * m2
        m3 = _INVERSES[j + 3] - r * m3
    return m0, m1, m2, m3


@njit(inline="always")
def exp_moments(a, ea):
    """``m_k = int_0^1 e^(-a t) t^k dt`` for ``k = 0..3``, given ``ea = e^-a``."""
    x = abs(a)
    # The fewest terms that keep the series' remainder below 3e-17 (the loops unroll: this
    # is on the hot path, and most steps of a sliding impact have a small |a|).
    if x < 0.03:
        return _moment_series(a, 8)  # 0.03^8 / 8! = 2e-17
    if x < SHORT_SERIES_BELOW:
        return _moment_series(a, SHORT_SERIES_TERMS)
    if x < SERIES_BELOW:
        return _moment_series(a, SERIES_TERMS)
    m0 = (1.0 - ea) / a
    m1 = (m0 - ea) / a
    m2 = (2.0 * m1 - ea) / a
    m3 = (3.0 * m2 - ea) / a
    return m0, m1, m2, m3


@njit(inline="always")
def _hermite_exp_integral(m0, m1, m2, m3, q0, dq0, q1, dq1, h):
    """``int_0^h e^(-a tau/h) q(tau) dtau`` for the cubic Hermite ``q`` with values
    ``q0, q1`` and slopes ``dq0, dq1`` at the ends (moments ``m_k`` of ``a``)."""
    return h * ((2.0 * m3 - 3.0 * m2 + m0) * q0 + (m3 - 2.0 * m2 + m1) * h * dq0
                + (3.0 * m2 - 2.0 * m3) * q1 + (m3 - m2) * h * dq1)


def _in_slip_loop(expr, caller_ir, callee_ir):
    """The inlining rule for ``tau_step``: inlined into the slip loop (``_slip_phase``),
    its hot path (called there, it made the game kernel ~5 % slower); called compiled, once
    for all, by the event location and the contact history (inlined there too, it was
    compiled twice over, a large share of the kernel's first compile)."""
    return caller_ir.func_id.func_name == "_slip_phase"


@njit(inline=_in_slip_loop)
def tau_step(c, w1, w2, imp, wfr, lam, h):
    """One Lawson RK4 step of length ``h`` in ``tau`` (kg) from the slip velocity
    ``(w1, w2)``, normal impulse ``imp`` and friction work ``wfr``, with the speed's rate
    frozen at ``-lam`` (1/kg; ``lam = -u . g`` at the start makes ``F(z_0)`` a pure turn)."""
    s0 = math.sqrt(w1 * w1 + w2 * w2)
    a1, a2 = _z_rate_at(c, lam, w1, w2, s0)
    hh = 0.5 * h
    b1, b2 = _z_rate(c, lam, w1 + hh * a1, w2 + hh * a2)
    c1, c2 = _z_rate(c, lam, w1 + hh * b1, w2 + hh * b2)
    d1, d2 = _z_rate(c, lam, w1 + h * c1, w2 + h * c2)
    k = h / 6.0
    z1 = w1 + k * (a1 + 2.0 * (b1 + c1) + d1)
    z2 = w2 + k * (a2 + 2.0 * (b2 + c2) + d2)
    e1, e2 = _z_rate(c, lam, z1, z2)  # FSAL stage: the embedded 3rd-order solution
    ea = math.exp(-lam * h)
    m0, m1, m2, m3 = exp_moments(lam * h, ea)
    n0, n1, n2, n3 = exp_moments(2.0 * lam * h, ea * ea)
    s1 = math.sqrt(z1 * z1 + z2 * z2)
    zdot = z1 * e1 + z2 * e2  # z . dz/dtau at the end
    # |z| and |z|^2 along the step: Hermite with slopes z.F/|z| and 2 z.F; at the start
    # F(z_0) . z_0 = |z_0|^2 (u . g + lam) = 0 by the choice of lam.
    d_imp = _hermite_exp_integral(m0, m1, m2, m3, s0, 0.0, s1, zdot / s1, h)
    d_wfr = -c.mu * _hermite_exp_integral(n0, n1, n2, n3, s0 * s0, 0.0, s1 * s1, 2.0 * zdot, h)
    # int v_t dI = int e^(-2 lam tau) z |z| dtau: Hermite of z |z|, with the slopes
    # F |z| + z (z . F) / |z| (the start's second term 0 as above).
    q1 = _hermite_exp_integral(n0, n1, n2, n3, w1 * s0, a1 * s0, z1 * s1,
                               e1 * s1 + z1 * zdot / s1, h)
    q2 = _hermite_exp_integral(n0, n1, n2, n3, w2 * s0, a2 * s0, z2 * s1,
                               e2 * s1 + z2 * zdot / s1, h)
    # The embedded estimate is the error of z at the end; inside the step it grows from 0,
    # and reaches I and W_fr weighted by the exponentials (taken as growing linearly).
    err = k * math.sqrt((d1 - e1) ** 2 + (d2 - e2) ** 2)
    # Quadrature errors: |z| and |z|^2 at the step's middle from the Hermite interpolant of
    # z, against the Hermite interpolants of |z| and |z|^2 integrated above (values at the
    # middle (q0 + q1)/2 + h (q0' - q1')/8, the start's slopes 0). The interpolation error
    # is ~16 d t^2 (1 - t)^2 for a difference d at the middle: 16/30 d h integrated, with
    # the exponential weight taken at the middle.
    k8 = 0.125 * h
    zm1 = 0.5 * (w1 + z1) + k8 * (a1 - e1)
    zm2 = 0.5 * (w2 + z2) + k8 * (a2 - e2)
    sm2 = zm1 * zm1 + zm2 * zm2
    shape = h * (16.0 / 30.0)
    quad_i = shape * math.sqrt(ea) * abs(math.sqrt(sm2) - 0.5 * (s0 + s1) + k8 * zdot / s1)
    quad_w = shape * ea * c.mu * abs(sm2 - 0.5 * (s0 * s0 + s1 * s1) + 2.0 * k8 * zdot)
    return TauStep(ea * z1, ea * z2, imp + d_imp, wfr + d_wfr, ea * err, err * h * m1 + quad_i,
                   2.0 * c.mu * s0 * err * h * n1 + quad_w, q1, q2)
