"""One ball-bat impact in the lab frame: geometry -> Delassus matrix -> contact solve.

``solve_impact`` is the scalar kernel that the Python API and the batch kernels call.
It takes plain floats and returns an ``Impact``, a named tuple whose fields
(``IMPACT_FIELDS``) callers scatter into struct-of-arrays outputs.
"""

import math
from collections import namedtuple

from mcbat.core import status as st
from mcbat.core.cabo2012.contact import solve_contact
from mcbat.core.cross_nathan2006.tangential import tangential_rebound
from mcbat.core.geometry import contact_frame
from mcbat.core.jit import njit
from mcbat.core.rigid_bodies import (
    apply_impulse,
    delassus_matrix,
    is_finite3,
    kinetic_energy,
    relative_contact_velocity,
)
from mcbat.core.vec3 import combine, dot

__all__ = ["IMPACT_FIELDS", "INPUT_FIELDS", "Impact", "ImpactInputs", "failed_impact",
           "solve_impact"]

ImpactInputs = namedtuple("ImpactInputs", [
    "ball_mass", "ball_radius", "ball_inertia_factor",
    "bat_mass", "bat_transverse_inertia", "bat_axial_inertia",
    "axial", "angle", "bat_radius", "bat_slope",
    "ball_vx_in", "ball_vy_in", "ball_vz_in", "ball_wx_in", "ball_wy_in", "ball_wz_in",
    "bat_vx_in", "bat_vy_in", "bat_vz_in", "bat_wx_in", "bat_wy_in", "bat_wz_in",
    "mu", "e", "e_x",
])
ImpactInputs.__doc__ = """The inputs of ``solve_impact`` (SI units; see its parameters)."""
INPUT_FIELDS = ImpactInputs._fields
"""Names of the fields of ``ImpactInputs``, in order (the rows of a batch's inputs)."""

Impact = namedtuple("Impact", [
    "status",
    "end_state",
    "ball_vx", "ball_vy", "ball_vz",
    "ball_wx", "ball_wy", "ball_wz",
    "bat_vx", "bat_vy", "bat_vz",
    "bat_wx", "bat_wy", "bat_wz",
    "normal_impulse",
    "stick_impulse",
    "compression_impulse",
    "tangential_impulse_1",
    "tangential_impulse_2",
    "compression_work",
    "normal_work",
    "friction_work",
    "stick_criterion",
    "energy_in",
    "energy_out",
    "rk4_steps",
])
Impact.__doc__ = """The result of ``solve_impact`` (fields named by ``IMPACT_FIELDS``)."""
IMPACT_FIELDS = Impact._fields
"""Names of the fields of ``Impact``, the result of ``solve_impact``, in order.

Units: velocities m/s, spins rad/s, impulses kg m/s, works and energies J. ``status`` and
``end_state`` are codes from ``mcbat.core.status``; ``stick_criterion`` is the paper's
``C = -W_n(I_s)`` (NaN without stick); ``tangential_impulse_1/2`` are the friction impulse
components along ``t1`` and ``t2``.
"""


@njit(inline="always")
def failed_impact(code, energy_in, rk4_steps=0):
    """The one place a failed result is built: status ``code``, every physical output NaN
    (``energy_in`` kept where it was computed)."""
    nan = math.nan
    return Impact(code, st.SLIDING, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan,
                  nan, nan, nan, nan, nan, nan, nan, nan, nan, energy_in, nan, rk4_steps)


# Valid ranges of the inputs (SI; docs/physics.md, "Valid inputs"). Outside them the
# arithmetic loses its meaning (under- or overflow of energies and impulses, an approach
# speed below the rounding of the contact velocity): status invalid_input.
MASS_RANGE = (1e-6, 1e15)  # kg, ball and bat (1e12: an immovable bat)
LENGTH_RANGE = (1e-5, 10.0)  # m, ball radius and bat radius at the contact
MAX_AXIAL = 100.0  # m, |axial|
INERTIA_RANGE = (1e-16, 1e15)  # kg m^2, bat inertias
MAX_SPEED = 1e5  # m/s, every velocity component
MAX_SPIN = 1e7  # rad/s, every spin component
MIN_APPROACH_SPEED = 1e-12  # m/s, |v_n| at the contact
MAX_MU = 1e3


@njit(inline="always")
def _within(x, low, high):
    return low <= x <= high


@njit(inline="always")
def _valid_bodies(ball_mass, ball_radius, ball_inertia_factor, bat_mass,
                  bat_transverse_inertia, bat_axial_inertia, axial, angle, radius, slope):
    """Bodies and contact within the valid ranges (NaN fails every comparison)."""
    m_lo, m_hi = MASS_RANGE
    l_lo, l_hi = LENGTH_RANGE
    i_lo, i_hi = INERTIA_RANGE
    return (_within(ball_mass, m_lo, m_hi) and _within(bat_mass, m_lo, m_hi)
            and _within(ball_radius, l_lo, l_hi) and _within(radius, l_lo, l_hi)
            and 0.0 < ball_inertia_factor <= 1.0
            and _within(bat_transverse_inertia, i_lo, i_hi)
            and _within(bat_axial_inertia, i_lo, i_hi)
            and abs(axial) <= MAX_AXIAL and math.isfinite(angle) and abs(slope) <= 1e3)


@njit(inline="always")
def _valid_motion(bvx, bvy, bvz, bwx, bwy, bwz, tvx, tvy, tvz, twx, twy, twz):
    """Velocities and spins within the valid ranges (NaN fails every comparison)."""
    speed = max(abs(bvx), abs(bvy), abs(bvz), abs(tvx), abs(tvy), abs(tvz))
    spin = max(abs(bwx), abs(bwy), abs(bwz), abs(twx), abs(twy), abs(twz))
    finite = True
    for x in (bvx, bvy, bvz, bwx, bwy, bwz, tvx, tvy, tvz, twx, twy, twz):
        finite = finite and math.isfinite(x)
    return finite and speed <= MAX_SPEED and spin <= MAX_SPIN


@njit
def solve_impact(inputs, accuracy):
    """Solve one rigid impact of a ball on a bat (lab frame, SI units).

    Parameters
    ----------
    inputs : ImpactInputs
        The fields below (floats).
    accuracy : mcbat.core.cabo2012.contact.Accuracy
        ``(steps, tolerance, max_steps)`` of
        ``mcbat.core.cabo2012.contact.solve_contact`` (``DEFAULT_ACCURACY`` there).

    Fields of ``inputs``
    --------------------
    ball_mass, ball_radius, ball_inertia_factor : float
        kg, m, and ``f`` in ``I_p = f m R^2``.
    bat_mass, bat_transverse_inertia, bat_axial_inertia : float
        kg and kg m^2 about the bat CM.
    axial, angle, bat_radius, bat_slope : float
        Contact point: axial position of the *contact point* on the bat surface, from
        the bat CM along the axis (m; on a tapered bat the ball's centre sits at
        ``axial - R r'/sqrt(1 + r'^2)``), azimuth (rad), bat radius there (m), profile
        slope dr/dz (0 for a cylinder).
    ball_v*_in, ball_w*_in, bat_v*_in, bat_w*_in : float
        Initial velocities (m/s) and spins (rad/s) of ball and bat.
    mu, e : float
        Friction coefficient and energetic restitution ``e*`` in [0, 1].
    e_x : float
        Tangential restitution in [0, 1] (Cross & Nathan 2006): a contact that ends stuck
        leaves with its incoming slip reversed and scaled by ``e_x``, within the friction
        its stick phase leaves unused, so the rebound vanishes continuously at the
        stick/slide boundary (``mcbat.core.cross_nathan2006``). The default 0 is the
        rigid model, exactly.

    Returns
    -------
    Impact
        A named tuple (fields ``IMPACT_FIELDS``). On a non-OK status the velocities are NaN
        (``failed_impact``). Inputs outside the valid ranges (``MASS_RANGE``,
        ``LENGTH_RANGE``, ... above; ``docs/physics.md``) give ``invalid_input``; whether a
        tapered bat's surface lets the ball touch only at the contact is checked by the
        callers that know the profile (``Bat.overlap``).
    """
    (ball_mass, ball_radius, ball_inertia_factor, bat_mass, bat_transverse_inertia,
     bat_axial_inertia, axial, angle, radius, slope, ball_vx, ball_vy, ball_vz, ball_wx,
     ball_wy, ball_wz, bat_vx, bat_vy, bat_vz, bat_wx, bat_wy, bat_wz, mu, e, e_x) = inputs
    nan = math.nan
    if not (_valid_bodies(ball_mass, ball_radius, ball_inertia_factor, bat_mass,
                          bat_transverse_inertia, bat_axial_inertia, axial, angle, radius,
                          slope)
            and _valid_motion(ball_vx, ball_vy, ball_vz, ball_wx, ball_wy, ball_wz, bat_vx,
                              bat_vy, bat_vz, bat_wx, bat_wy, bat_wz)
            and 0.0 <= e_x <= 1.0 and mu <= MAX_MU):
        return failed_impact(st.INVALID_INPUT, nan)
    t1, t2, t3, r_c = contact_frame(axial, angle, radius, slope)
    ball_v = (ball_vx, ball_vy, ball_vz)
    ball_w = (ball_wx, ball_wy, ball_wz)
    bat_v = (bat_vx, bat_vy, bat_vz)
    bat_w = (bat_wx, bat_wy, bat_wz)
    k11, k12, k13, k22, k23, k33 = delassus_matrix(
        ball_mass, ball_radius, ball_inertia_factor,
        bat_mass, bat_transverse_inertia, bat_axial_inertia, t1, t2, t3, r_c)
    v0 = relative_contact_velocity(ball_radius, t3, r_c, ball_v, ball_w, bat_v, bat_w)
    if -MIN_APPROACH_SPEED < dot(v0, t3) < 0.0:  # approaching, too slowly to mean anything
        return failed_impact(st.INVALID_INPUT, nan)
    energy_in = kinetic_energy(
        ball_mass, ball_radius, ball_inertia_factor,
        bat_mass, bat_transverse_inertia, bat_axial_inertia, ball_v, ball_w, bat_v, bat_w)
    r = solve_contact(k11, k12, k13, k22, k23, k33, dot(v0, t1), dot(v0, t2), dot(v0, t3),
                      mu, e, accuracy.steps, accuracy.tolerance, accuracy.max_steps)
    if r.status != st.OK:
        return failed_impact(r.status, energy_in)
    code, end_state, n_rk4 = r.status, r.end_state, r.rk4_steps
    p1, p2, i_f, w_fr = r.p1, r.p2, r.i_f, r.w_fr
    if e_x > 0.0 and end_state == st.STUCK:
        # Tangential compliance gives back part of the friction loss as reversed slip,
        # within the friction the stick phase [I_s, I_f] leaves unused; friction_work
        # becomes the net work of the tangential force (still <= 0).
        dp1, dp2, returned = tangential_rebound(
            k11, k12, k13, k22, k23, k33, dot(v0, t1), dot(v0, t2), dot(v0, t3),
            p1, p2, i_f, r.i_s, w_fr, mu, e_x)
        p1 += dp1
        p2 += dp2
        w_fr += returned
    impulse = combine(p1, t1, p2, t2, i_f, t3)
    ball_v, ball_w, bat_v, bat_w = apply_impulse(
        impulse, ball_mass, ball_radius, ball_inertia_factor,
        bat_mass, bat_transverse_inertia, bat_axial_inertia, t3, r_c,
        ball_v, ball_w, bat_v, bat_w)
    energy_out = kinetic_energy(
        ball_mass, ball_radius, ball_inertia_factor,
        bat_mass, bat_transverse_inertia, bat_axial_inertia, ball_v, ball_w, bat_v, bat_w)
    # Finite inputs can still overflow or underflow (speeds ~1e154, radii ~1e-160): a result
    # that is not finite is flagged, never passed off as ok.
    if not (is_finite3(ball_v) and is_finite3(ball_w) and is_finite3(bat_v)
            and is_finite3(bat_w) and math.isfinite(i_f) and math.isfinite(energy_out)
            and math.isfinite(energy_in)):
        return failed_impact(st.INVALID_INPUT, energy_in, n_rk4)
    return Impact(
        code, end_state,
        ball_v[0], ball_v[1], ball_v[2], ball_w[0], ball_w[1], ball_w[2],
        bat_v[0], bat_v[1], bat_v[2], bat_w[0], bat_w[1], bat_w[2],
        i_f, r.i_s, r.i_c, p1, p2, r.w_c, r.w_n, w_fr, -r.w_n_stick, energy_in, energy_out,
        n_rk4,
    )
