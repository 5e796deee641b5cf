"""Rigid-body impulse mechanics of a ball (sphere) and a bat (axisymmetric body).

Conventions (``docs/physics.md``): an impulse ``P`` acts on the ball at the contact point and
``-P`` on the bat. The ball's inertia is ``f m R^2`` (isotropic); the bat's inertia about
its CM is ``diag(I_t, I_t, I_3)`` in the lab frame (``z`` along the bat axis).
"""

import math

from mcbat.core.jit import njit
from mcbat.core.vec3 import add, cross, dot, scale, sub

__all__ = ["apply_impulse", "delassus_matrix", "is_finite3", "kinetic_energy",
           "relative_contact_velocity"]


@njit
def delassus_matrix(
    ball_mass, ball_radius, ball_inertia_factor,
    bat_mass, bat_transverse_inertia, bat_axial_inertia,
    t1, t2, t3, r_c,
):
    """Delassus (inverse effective mass) matrix ``K`` in the contact basis.

    ``K = (1/m_p + 1/m_b) 1 - [rho]x I_p^-1 [rho]x - [r_c]x I_b^-1 [r_c]x`` with
    ``rho = r_c - r_p = -R t3``; a contact impulse ``P`` changes the relative contact
    velocity by ``K P``. Units: 1/kg (m/s per kg m/s).

    Returns
    -------
    k11, k12, k13, k22, k23, k33 : float
        The six independent entries of the symmetric matrix, in the ``(t1, t2, t3)`` basis.
    """
    inv_mass = 1.0 / ball_mass + 1.0 / bat_mass
    # The ball's rotational term acts only tangentially: R^2 / I_p (1 - t3 t3^T).
    ball_rot = 1.0 / (ball_inertia_factor * ball_mass)
    c1 = cross(r_c, t1)
    c2 = cross(r_c, t2)
    c3 = cross(r_c, t3)
    it = 1.0 / bat_transverse_inertia
    i3 = 1.0 / bat_axial_inertia

    def bat_term(a, b):
        return (a[0] * b[0] + a[1] * b[1]) * it + a[2] * b[2] * i3

    k11 = inv_mass + ball_rot + bat_term(c1, c1)
    k12 = bat_term(c1, c2)
    k13 = bat_term(c1, c3)
    k22 = inv_mass + ball_rot + bat_term(c2, c2)
    k23 = bat_term(c2, c3)
    k33 = inv_mass + bat_term(c3, c3)
    return k11, k12, k13, k22, k23, k33


@njit
def relative_contact_velocity(ball_radius, t3, r_c, ball_v, ball_w, bat_v, bat_w):
    """Velocity of the ball's contact point relative to the bat's (lab frame, m/s)."""
    rho = scale(-ball_radius, t3)
    return sub(add(ball_v, cross(ball_w, rho)), add(bat_v, cross(bat_w, r_c)))


@njit
def apply_impulse(
    impulse, ball_mass, ball_radius, ball_inertia_factor,
    bat_mass, bat_transverse_inertia, bat_axial_inertia,
    t3, r_c, ball_v, ball_w, bat_v, bat_w,
):
    """Velocities after the contact impulse ``impulse`` (kg m/s, lab frame) on the ball.

    Returns ``(ball_v, ball_w, bat_v, bat_w)`` as 3-tuples (m/s, rad/s).
    """
    rho = scale(-ball_radius, t3)
    ball_inertia = ball_inertia_factor * ball_mass * ball_radius * ball_radius
    new_ball_v = add(ball_v, scale(1.0 / ball_mass, impulse))
    new_ball_w = add(ball_w, scale(1.0 / ball_inertia, cross(rho, impulse)))
    new_bat_v = sub(bat_v, scale(1.0 / bat_mass, impulse))
    torque = cross(r_c, impulse)
    new_bat_w = (
        bat_w[0] - torque[0] / bat_transverse_inertia,
        bat_w[1] - torque[1] / bat_transverse_inertia,
        bat_w[2] - torque[2] / bat_axial_inertia,
    )
    return new_ball_v, new_ball_w, new_bat_v, new_bat_w


@njit
def kinetic_energy(
    ball_mass, ball_radius, ball_inertia_factor,
    bat_mass, bat_transverse_inertia, bat_axial_inertia,
    ball_v, ball_w, bat_v, bat_w,
):
    """Total kinetic energy of ball and bat (J)."""
    ball_inertia = ball_inertia_factor * ball_mass * ball_radius * ball_radius
    return 0.5 * (
        ball_mass * dot(ball_v, ball_v)
        + ball_inertia * dot(ball_w, ball_w)
        + bat_mass * dot(bat_v, bat_v)
        + bat_transverse_inertia * (bat_w[0] * bat_w[0] + bat_w[1] * bat_w[1])
        + bat_axial_inertia * bat_w[2] * bat_w[2]
    )


@njit
def is_finite3(a):
    """True if all three components of ``a`` are finite."""
    return math.isfinite(a[0]) and math.isfinite(a[1]) and math.isfinite(a[2])
