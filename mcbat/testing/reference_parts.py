"""The pieces of the reference integrator
``mcbat.testing.cabo2012_reference.reference_impact``: the contact basis and the two
bodies re-derived with numpy, the impulse-to-velocity map ``K`` obtained numerically, the
re-slip direction, the chained ``solve_ivp`` segments and the tangential rebound. Like the
integrator, independent of the kernel: numpy and scipy only.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = ["RESLIP_SAMPLES", "Bodies", "contact_basis", "integrate", "numerical_k",
           "reslip_direction", "tangential_rebound"]

# Samples of the azimuth scan that brackets the re-slip directions before brentq.
RESLIP_SAMPLES = 3600

def _cross(a, b):
    """Cross product of two 3-vectors (np.cross is ~10x slower on tiny arrays)."""
    return np.array([a[1] * b[2] - a[2] * b[1],
                     a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def contact_basis(axial, angle, radius, slope):
    """Contact basis and contact point, re-derived with numpy.

    Parameters
    ----------
    axial : float
        Axial position of the contact from the bat CM, m.
    angle : float
        Azimuth of the contact point, rad.
    radius : float
        Bat radius at the contact, m.
    slope : float
        Profile slope dr/dz (dimensionless).

    Returns
    -------
    t1, t2, t3, r_c : numpy.ndarray
        Azimuthal tangent, meridional tangent, outward normal (unit), contact point (m).
    """
    e_r = np.array([math.cos(angle), math.sin(angle), 0.0])
    k = np.array([0.0, 0.0, 1.0])
    # Surface point (r(z) e_r, z): the tangent along z is r' e_r + k, the azimuthal one
    # e_phi = k x e_r; the outward normal is perpendicular to both.
    t1 = _cross(k, e_r)
    meridian = slope * e_r + k
    t2 = meridian / np.linalg.norm(meridian)
    t3 = _cross(t1, t2)
    r_c = radius * e_r + axial * k
    return t1, t2, t3, r_c


class Bodies:
    """Masses, inertias and contact geometry; maps impulse rates to velocity rates."""

    def __init__(self, ball_mass, ball_radius, ball_inertia_factor, bat_mass,
                 bat_transverse_inertia, bat_axial_inertia, t3, r_c):
        self.m_p = float(ball_mass)
        self.i_p = float(ball_inertia_factor) * self.m_p * float(ball_radius) ** 2
        self.m_b = float(bat_mass)
        # Bat inertia is diagonal in the lab frame (z along the bat axis).
        self.i_b_inv = 1.0 / np.array(
            [bat_transverse_inertia, bat_transverse_inertia, bat_axial_inertia], dtype=float)
        self.rho = -float(ball_radius) * t3  # contact point from the ball centre
        self.r_c = r_c

    def velocity_rates(self, p_rate):
        """Rates of ``(v_p, w_p, v_b, w_b)`` (12,) for impulse rate ``p_rate`` on the ball."""
        out = np.empty(12)
        out[0:3] = p_rate / self.m_p
        out[3:6] = _cross(self.rho, p_rate) / self.i_p
        out[6:9] = -p_rate / self.m_b
        out[9:12] = -self.i_b_inv * _cross(self.r_c, p_rate)
        return out

    def relative_velocity(self, y):
        """Relative velocity (m/s) of the ball's contact point with respect to the bat's."""
        return (y[0:3] + _cross(y[3:6], self.rho)
                - y[6:9] - _cross(y[9:12], self.r_c))

    def energy(self, y):
        """Kinetic energy (J) of both bodies."""
        return 0.5 * (self.m_p * y[0:3] @ y[0:3] + self.i_p * y[3:6] @ y[3:6]
                      + self.m_b * y[6:9] @ y[6:9] + (y[9:12] ** 2 / self.i_b_inv).sum())


def numerical_k(bodies, basis):
    """Impulse-to-velocity map in the contact basis, from unit impulses.

    The relative velocity is linear in the body velocities, which are linear in the
    impulse, so applying each unit impulse to zero velocities gives the column of ``K``
    exactly (no difference of large numbers).

    Returns
    -------
    numpy.ndarray
        (3, 3) matrix, rows and columns in the basis ``(t1, t2, t3)``, units 1/kg.
    """
    k = np.empty((3, 3))
    for j in range(3):
        y = np.zeros(14)
        y[:12] = bodies.velocity_rates(basis[j])
        k[:, j] = basis @ bodies.relative_velocity(y)
    return k


def reslip_direction(k, mu):
    """Unit direction ``u*`` (2,) with ``K_tn - mu K_tt u* = lambda u*``, largest lambda > 0.

    Scans the azimuth of ``u`` for sign changes of the 2D cross product ``u x g(u)``,
    ``g = K_tn - mu K_tt u``, refines each with brentq and keeps the roots with
    ``u . g > 0``. Returns None if there is none.
    """
    k_tt = k[:2, :2]
    k_tn = k[:2, 2]

    def g(phi):
        return k_tn - mu * k_tt @ np.array([math.cos(phi), math.sin(phi)])

    def cross(phi):
        gv = g(phi)
        return math.cos(phi) * gv[1] - math.sin(phi) * gv[0]

    phis = np.linspace(0.0, 2.0 * math.pi, RESLIP_SAMPLES + 1)
    u_all = np.array([np.cos(phis), np.sin(phis)])
    g_all = k_tn[:, None] - mu * (k_tt @ u_all)
    values = u_all[0] * g_all[1] - u_all[1] * g_all[0]
    roots = []
    for a, b, fa, fb in zip(phis[:-1], phis[1:], values[:-1], values[1:]):
        if fa == 0.0:
            roots.append(a)
        elif fa * fb < 0.0:
            roots.append(brentq(cross, a, b, xtol=1e-15, rtol=4.0 * np.finfo(float).eps,
                                 maxiter=200))
    best, best_lambda = None, 0.0
    for phi in roots:
        u = np.array([math.cos(phi), math.sin(phi)])
        lam = float(u @ g(phi))
        if lam > best_lambda:
            best, best_lambda = u, lam
    return best


def integrate(rhs, span, y, events, rtol, atol):
    """``solve_ivp`` (DOP853) over ``span`` with terminal ``events``: ``(t, y, name)`` at the
    earliest event that fired, or at the end of the span with ``name`` None."""
    sol = solve_ivp(rhs, span, y, method="DOP853", events=events, rtol=rtol, atol=atol)
    if sol.status == -1:
        raise RuntimeError(f"solve_ivp failed: {sol.message}")
    if sol.status == 0:
        return sol.t[-1], sol.y[:, -1], None
    fired = [(te[0], j) for j, te in enumerate(sol.t_events) if len(te)]
    t, j = min(fired)
    return t, sol.y_events[j][0], events[j].__name__


def tangential_rebound(bodies, basis, y0, y_stick, y, mu, e_x):
    """Reverse the incoming slip by ``e_x`` with a tangential impulse of the stick phase.

    ``y0``, ``y_stick`` and ``y`` are the states at incidence, where slip stopped (``I_s``)
    and at separation (``I_f``). Independent of the kernel's closed forms: the impulse comes
    from a 2x2 solve with the numerical ``K``, the stick phase's impulse from the ball's
    momentum change between ``y_stick`` and ``y``, and the scale ``s`` from root finding on
    the constraints evaluated on the bodies themselves: the rebound within the friction the
    stick phase leaves unused (``|P_stick,t| + s |dP| <= mu P_stick,n``), net friction work
    (integrated ``W_fr`` plus the energy given back) not positive, kinetic energy not above
    the initial, normal relative velocity not negative.
    """
    t1, t2, t3 = basis
    v_in = bodies.relative_velocity(y0)
    target = -e_x * np.array([v_in @ t1, v_in @ t2])
    now = bodies.relative_velocity(y)
    k = numerical_k(bodies, basis)
    dp = np.linalg.solve(k[:2, :2], target - np.array([now @ t1, now @ t2]))
    dp_lab = dp[0] * t1 + dp[1] * t2

    def moved(s):
        out = y.copy()
        out[:12] += bodies.velocity_rates(s * dp_lab)
        out[13] += bodies.energy(out) - bodies.energy(y)
        return out

    stick = bodies.m_p * (y[0:3] - y_stick[0:3])  # impulse on the ball while stuck
    stick_normal = stick @ t3
    stick_tangential = np.linalg.norm(stick - stick_normal * t3)
    energy_in = bodies.energy(y0)

    def spare_friction(s):
        return stick_tangential + s * np.linalg.norm(dp_lab) - mu * stick_normal

    def friction(s):
        return moved(s)[13]

    def energy(s):
        return bodies.energy(moved(s)) - energy_in

    def receding(s):
        return -(bodies.relative_velocity(moved(s)) @ t3)

    s = 1.0
    for g in (spare_friction, friction, energy, receding):
        if g(s) > 0.0:
            s = brentq(g, 0.0, s, xtol=1e-15) if g(0.0) < 0.0 else 0.0
    return moved(s)
