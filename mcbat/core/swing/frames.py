"""Field frame <-> bat frame: the pitch, the swing and the contact as jitted functions.

Field frame (Statcast / PITCHf/x): origin at the point of home plate, ``z`` up, ``y``
towards the pitcher, ``x`` towards the first-base side. Bat frame (``docs/physics.md``):
origin at the bat CM, ``k`` along the axis towards the barrel end. All angles in rad,
speeds in m/s, spins in rad/s. The equations and their sources: ``README.md``.
"""

import math
from collections import namedtuple

from mcbat.core.jit import njit
from mcbat.core.vec3 import cross, dot, norm, scale, sub

__all__ = ["SWEET_SPOT_FROM_BARREL_END", "BatBody", "GameContact", "Pitch", "Swing",
           "bat_frame", "from_frame", "pitch_state", "swing_state", "to_frame"]

#: Statcast measures the bat speed at the "sweet spot", 6 in from the barrel end (m).
SWEET_SPOT_FROM_BARREL_END = 0.1524

Pitch = namedtuple("Pitch", ("speed", "vertical_approach_angle", "horizontal_approach_angle",
                             "spin_rate", "spin_axis", "spin_efficiency", "gyro_sign"))
"""The pitch at the plate: m/s, rad (VAA < 0 descending, HAA > 0 moving towards ``+x``),
rad/s, Statcast spin axis (rad; pi = pure backspin), fraction of the spin that is
transverse, and the sense (+1/-1) of the gyro part along the direction of travel."""

Swing = namedtuple("Swing", ("handedness", "bat_speed", "attack_angle", "attack_direction",
                             "vertical_bat_angle", "pivot"))
"""The swing at contact: +1 right-, -1 left-handed; sweet-spot speed (m/s); attack
angle, attack direction (positive towards the batter's opposite field) and vertical bat
angle (rad); pivot: distance of the rotation centre from the knob along the axis (m)."""

BatBody = namedtuple("BatBody", ("length", "cm_from_knob"))
"""The bat's length and the CM's distance from the knob (m)."""

GameContact = namedtuple("GameContact", ("from_barrel_end", "undercut"))
"""Where along the bat the ball hits (m from the barrel end), and the undercut ``D``
(m; positive: the ball's centre line passes above the bat axis)."""


@njit
def pitch_state(pitch):
    """Velocity and spin of the pitched ball in the field frame.

    Returns ``(ok, v, w)``; ``ok`` is False for a pitch whose direction is vertical (no
    transverse plane) or for non-finite input.
    """
    cv = math.cos(pitch.vertical_approach_angle)
    ch = math.cos(pitch.horizontal_approach_angle)
    sh = math.sin(pitch.horizontal_approach_angle)
    d = (cv * sh, -cv * ch, math.sin(pitch.vertical_approach_angle))
    # Transverse basis seen from behind the plate: e1 = unit(z x d) = (cos h, sin h, 0)
    # (= +x for d = -y), e2 = d x e1 (= +z for d = -y).
    if not cv > 1e-12:
        z3 = (math.nan, math.nan, math.nan)
        return False, z3, z3
    e1 = (ch, sh, 0.0)
    e2 = cross(d, e1)
    # Statcast's spin axis: the Magnus direction m on the clock face, pi (180 deg) = up
    # (pure backspin), 0 = down (topspin), pi/2 (90 deg) = towards +x (first base).
    s, c = math.sin(pitch.spin_axis), math.cos(pitch.spin_axis)
    m = (s * e1[0] - c * e2[0], s * e1[1] - c * e2[1], s * e1[2] - c * e2[2])
    eff = pitch.spin_efficiency
    transverse = pitch.spin_rate * eff
    gyro = pitch.gyro_sign * pitch.spin_rate * math.sqrt(max(0.0, 1.0 - eff * eff))
    axis = cross(d, m)  # w_T along d x m gives a Magnus force w x v along +m
    w = (transverse * axis[0] + gyro * d[0], transverse * axis[1] + gyro * d[1],
         transverse * axis[2] + gyro * d[2])
    v = scale(pitch.speed, d)
    ok = (math.isfinite(v[0]) and math.isfinite(v[1]) and math.isfinite(v[2])
          and math.isfinite(w[0]) and math.isfinite(w[1]) and math.isfinite(w[2]))
    return ok, v, w


@njit
def swing_state(swing, bat):
    """The bat's axis, CM velocity and angular velocity in the field frame.

    The sweet spot (6 in from the barrel end) moves at ``bat_speed`` along
    ``u = (cos a sin p, cos a cos p, sin a)`` (``a`` attack angle, ``p`` attack
    direction; a right-handed batter's opposite field is ``+x``). The axis ``n`` (knob to
    barrel) has elevation the vertical bat angle ``b`` and is perpendicular to ``u``: in
    the horizontal basis ``P = (cos p, -sin p)``, ``Q = (sin p, cos p)``,
    ``n = A P + B Q + sin(b) z`` with ``B = -sin(b) tan(a)``, ``A = +sqrt(cos^2 b - B^2)``
    (the barrel on the batter's far side). No real ``A`` exists when
    ``|tan a tan b| >= 1``: the angles are inconsistent (``ok`` False). A left-handed
    batter is the mirror image in ``x``. The bat rotates about the pivot with
    ``W = (bat_speed / L) n x u``, ``L`` the pivot's distance from the sweet spot, so
    the CM moves at ``bat_speed (cm_from_knob - pivot) / L`` along ``u``.

    Returns ``(ok, n, v_cm, w)``.
    """
    a, p, b = swing.attack_angle, swing.attack_direction, swing.vertical_bat_angle
    ca, sa = math.cos(a), math.sin(a)
    cp, sp = math.cos(p), math.sin(p)
    cb, sb = math.cos(b), math.sin(b)
    u = (ca * sp, ca * cp, sa)
    big_b = -sb * sa / ca
    a2 = cb * cb - big_b * big_b
    lever = bat.length - SWEET_SPOT_FROM_BARREL_END - swing.pivot
    nan3 = (math.nan, math.nan, math.nan)
    if not (a2 > 1e-12 and ca > 1e-12 and lever > 0.0 and math.isfinite(swing.bat_speed)
            and (swing.handedness == 1.0 or swing.handedness == -1.0)):
        return False, nan3, nan3, nan3
    big_a = math.sqrt(a2)
    n = (big_a * cp + big_b * sp, -big_a * sp + big_b * cp, sb)
    if swing.handedness < 0.0:
        n = (-n[0], n[1], n[2])
        u = (-u[0], u[1], u[2])
    omega = scale(swing.bat_speed / lever, cross(n, u))
    v_cm = scale(swing.bat_speed * (bat.cm_from_knob - swing.pivot) / lever, u)
    return True, n, v_cm, omega


@njit
def bat_frame(axis, v_cm, omega, ball_v, axial):
    """The bat frame's basis ``(i, j, k)`` in field components, and the sign of "up".

    ``k`` is the bat axis; ``i = -unit(w_perp)``, ``w_perp`` the part perpendicular to the
    axis of the ball's velocity relative to the point of the axis at the contact
    (``axial`` m from the CM), so the ball comes from ``+i`` (approach azimuth 0, as in
    the paper's Sec. V); ``j = k x i``. ``up`` is +1 when ``j`` has a non-negative
    vertical component, else -1: the undercut ``D`` is the impact parameter ``b = up D``.

    Returns ``(ok, i, j, k, up, relative)``, ``relative`` the full relative velocity.
    """
    point_v = (v_cm[0] + omega[1] * axis[2] * axial - omega[2] * axis[1] * axial,
               v_cm[1] + omega[2] * axis[0] * axial - omega[0] * axis[2] * axial,
               v_cm[2] + omega[0] * axis[1] * axial - omega[1] * axis[0] * axial)
    w = sub(ball_v, point_v)
    along = dot(w, axis)
    w_perp = (w[0] - along * axis[0], w[1] - along * axis[1], w[2] - along * axis[2])
    size = norm(w_perp)
    if not size > 0.0:
        z3 = (math.nan, math.nan, math.nan)
        return False, z3, z3, z3, 1.0, w
    i = scale(-1.0 / size, w_perp)
    j = cross(axis, i)
    up = 1.0 if j[2] >= 0.0 else -1.0
    return True, i, j, axis, up, w


@njit(inline="always")
def to_frame(i, j, k, a):
    """Components of the field vector ``a`` in the basis ``(i, j, k)``."""
    return (dot(a, i), dot(a, j), dot(a, k))


@njit(inline="always")
def from_frame(i, j, k, a):
    """The field vector with components ``a`` in the basis ``(i, j, k)``."""
    return (a[0] * i[0] + a[1] * j[0] + a[2] * k[0],
            a[0] * i[1] + a[1] * j[1] + a[2] * k[1],
            a[0] * i[2] + a[1] * j[2] + a[2] * k[2])
