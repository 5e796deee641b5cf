"""Tangential rebound of a gripping contact (Cross & Nathan's ``e_x``), as an impulse.

The rigid model (``mcbat.core.cabo2012``) ends a gripping impact with zero tangential
slip. A ball and a bat are not rigid: the contact patch shears while it grips, stores
elastic energy and gives part of it back, so the ball leaves with its slip *reversed*.
Cross & Nathan (2006) describe this by a tangential coefficient of restitution

    v_t,out = -e_x v_t,in,

``v_t`` the tangential velocity of the ball's contact point relative to the bat surface.
``tangential_rebound`` turns that into an extra tangential impulse delivered during the
rigid solution's stick phase, within the friction that phase leaves unused and within the
energy budget (see ``README.md``). It vanishes continuously where the contact stops
gripping: at the stick/slide boundary the spare friction is zero.
"""

import math

from mcbat.core.jit import njit

__all__ = ["tangential_rebound"]


@njit
def tangential_rebound(
    k11, k12, k13, k22, k23, k33,
    v01, v02, v0n,
    p1, p2, normal_impulse, stick_impulse, friction_work,
    mu, e_x,
):
    """Extra tangential impulse that reverses the slip, delivered during the stick phase.

    Parameters
    ----------
    k11, k12, k13, k22, k23, k33 : float
        Delassus matrix ``K`` in the contact frame ``(t1, t2, t3)`` (1/kg).
    v01, v02, v0n : float
        Relative contact velocity at incidence (m/s).
    p1, p2, normal_impulse : float
        The rigid solution's tangential impulses and normal impulse ``I_f`` (kg m/s).
    stick_impulse : float
        The rigid solution's stick impulse ``I_s`` (kg m/s): where the slip stopped and the
        stick phase ``[I_s, I_f]`` began (0 for incidence without slip; NaN if the contact
        slid to the end, which gives no rebound).
    friction_work : float
        The rigid solution's friction work ``W_fr <= 0`` (J).
    mu, e_x : float
        Friction coefficient and tangential restitution in ``[0, 1]``.

    Returns
    -------
    dp1, dp2 : float
        Tangential impulse to add (kg m/s), ``(0, 0)`` when ``e_x = 0`` or there is no stick
        phase.
    work : float
        Its work on the bodies (J, >= 0): the elastic energy the contact gives back.

    Notes
    -----
    The target is ``v_t = -e_x v_t,in`` at separation, i.e. ``dP = K_tt^-1 (-e_x v_t,in -
    v_t)``. From a stuck end (``v_t = 0``) it gives back the energy
    ``e_x^2 v_t,in . K_tt^-1 v_t,in / 2``: for an uncoupled contact (``K_tn = 0``) exactly the
    share ``e_x^2`` of the rigid friction loss ``|W_fr|``, as for a tangential spring of
    restitution ``e_x``.

    The rebound belongs to the stick phase: it is delivered over ``[I_s, I_f]`` at the
    uniform rate ``s dP / D`` per unit normal impulse, ``D = I_f - I_s``, on top of the
    holding rate ``f = -K_tt^-1 K_tn``. (The outgoing velocities depend only on the total
    impulse, so this gives the same state as a kick at the end; what it changes is the
    friction that limits it.) ``s`` is the largest value in ``[0, 1]`` that keeps

    (a) the rebound within the friction the stick phase leaves unused,
        ``s |dP| <= (mu - |f|) D``. This implies the stick phase's friction cone
        ``|f D + s dP| <= mu D`` (and hence the cone of the whole impact,
        ``|P_t + s dP| <= mu I_f``), and it goes to zero linearly at both edges of gripping:
        a stick phase that shrinks to nothing (``I_s -> I_f``) and a holding rate that reaches
        the friction limit (``|f| -> mu``, beyond which the rigid contact re-slips). The cone
        ``|f D + s dP| <= mu D`` alone would not: a rebound against ``f`` keeps up to
        ``2 |f| D`` of room there;
    (b) the energy given back within the friction loss ``|W_fr|``: the contact cannot return
        more than the tangential force took, so its net work stays <= 0 and no energy is
        created (only a coupled contact or ``e_x`` near 1 reach this bound; at ``e_x = 1`` on
        an uncoupled contact it holds with equality, to the accuracy of ``W_fr``);
    (c) the bodies separating, ``v_n >= 0`` at the end.

    The normal phase (``I_f``, ``W_n``) stays the rigid model's: the rebound's coupling to
    ``v_n`` through ``K_nt`` during the stick phase is not fed back into the separation
    rule; (c) keeps the outgoing ``v_n`` receding.
    """
    if not e_x > 0.0:
        return 0.0, 0.0, 0.0
    stick_phase = normal_impulse - stick_impulse
    if not stick_phase > 0.0:  # no stick phase (NaN: slid to the end)
        return 0.0, 0.0, 0.0
    det = k11 * k22 - k12 * k12
    if not det > 0.0:
        return 0.0, 0.0, 0.0
    # The stick phase's holding rate f = -K_tt^-1 K_tn (as cabo2012.contact's
    # stick_impulse_rate; not imported from there, which would be a circular import).
    f1 = -(k22 * k13 - k12 * k23) / det
    f2 = -(k11 * k23 - k12 * k13) / det
    spare = (mu - math.sqrt(f1 * f1 + f2 * f2)) * stick_phase  # friction left unused
    if not spare > 0.0:
        return 0.0, 0.0, 0.0
    # Rigid velocities at separation.
    vt1 = v01 + k11 * p1 + k12 * p2 + k13 * normal_impulse
    vt2 = v02 + k12 * p1 + k22 * p2 + k23 * normal_impulse
    vn = v0n + k13 * p1 + k23 * p2 + k33 * normal_impulse
    r1 = -e_x * v01 - vt1
    r2 = -e_x * v02 - vt2
    dp1 = (k22 * r1 - k12 * r2) / det
    dp2 = (k11 * r2 - k12 * r1) / det
    size = math.sqrt(dp1 * dp1 + dp2 * dp2)
    if not size > 0.0:
        return 0.0, 0.0, 0.0
    # (a) the stick phase's spare friction.
    s = min(1.0, spare / size)
    # (b) energy: s (v_t . dP) + s^2 (dP . K_tt dP) / 2 <= |W_fr| (and <= the whole loss).
    lin = vt1 * dp1 + vt2 * dp2
    quad = 0.5 * (k11 * dp1 * dp1 + 2.0 * k12 * dp1 * dp2 + k22 * dp2 * dp2)
    # The rigid impact's whole loss, exactly from the kinetic form -(v0 + v).P / 2 (not from
    # W_n + W_fr, which carry the slip integration's error).
    lost = -0.5 * ((v01 + vt1) * p1 + (v02 + vt2) * p2 + (v0n + vn) * normal_impulse)
    budget = max(min(-friction_work, lost), 0.0)
    if lin * s + quad * s * s > budget:
        s = min(s, (-lin + math.sqrt(max(lin * lin + 4.0 * quad * budget, 0.0)))
                / (2.0 * quad))
    # (c) separation: v_n + s (K_nt . dP) >= 0.
    dvn = k13 * dp1 + k23 * dp2
    if dvn < 0.0:
        s = min(s, max(vn, 0.0) / -dvn)
    s = max(s, 0.0)
    dp1 *= s
    dp2 *= s
    return dp1, dp2, s * lin + s * s * quad
