"""The pitch at the plate and the batted ball's direction, from Statcast's published fits.

Pure numpy, element-wise over arrays; NaN in, NaN out (nothing is guessed).

**The pitch.** Statcast publishes each pitch as a constant-acceleration fit (the
"9-parameter fit" of PITCHf/x): velocity ``(vx0, vy0, vz0)`` (ft/s) and acceleration
``(ax, ay, az)`` (ft/s^2) at the moment the ball crosses ``y0 = 50 ft``, in the field
frame (``x`` to the first-base side, ``y`` from the plate to the mound, ``z`` up). With
constant acceleration, the velocity at the plane ``y = y_f`` follows from
``vy_f^2 = vy0^2 + 2 ay (y_f - y0)`` without the time: ``vy_f = -sqrt(vy0^2 - 2 ay (y0 -
y_f))`` (the ball moves towards ``-y``), ``t = (vy_f - vy0) / ay``, ``vx_f = vx0 + ax t``,
``vz_f = vz0 + az t``. The angles are those of mcbat's game keys (``mcbat.core.swing``:
the pitch's direction is ``(cos V sin H, -cos V cos H, sin V)``), so that a row's values
rebuild its velocity exactly:

- ``V = atan2(vz_f, hypot(vx_f, vy_f))``: the elevation of the velocity, < 0 descending;
- ``H = atan2(vx_f, -vy_f)``: > 0 moving towards ``+x``.

The vertical approach angle as the public literature writes it, ``atan(vz_f / vy_f)``
(sign set so that descending is negative), is the angle in the y-z plane, not the
elevation of the full velocity: ``tan`` of one is ``tan`` of the other over ``cos H``, a
difference of about ``sin V cos V H^2 / 2``: under 0.05 deg for ``|H| < 5 deg`` and
``|V| < 12 deg`` (tested on the shipped pitches).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["FT_S_PER_MPH", "HOME_PLATE_HC", "PLATE_FRONT_FT", "Y0_FT", "plate_crossing",
           "spray_angle"]

FT_S_PER_MPH = 5280.0 / 3600.0
"""Feet per second in one mile per hour (exact)."""
Y0_FT = 50.0
"""The plane of Statcast's published fit, ft from the point of home plate."""
PLATE_FRONT_FT = 17.0 / 12.0
"""The front of home plate (its edge nearest the pitcher), ft from its point."""
HOME_PLATE_HC = (125.42, 198.27)
"""Home plate in the spray-chart coordinates ``(hc_x, hc_y)`` (the value the Statcast
literature uses; the chart's units are about 2.5 ft)."""


def plate_crossing(vx0: ArrayLike, vy0: ArrayLike, vz0: ArrayLike, ax: ArrayLike,
                   ay: ArrayLike, az: ArrayLike, y0: float = Y0_FT,
                   y_plate: float = PLATE_FRONT_FT
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The pitch's speed and approach angles where it crosses ``y = y_plate``.

    Parameters
    ----------
    vx0, vy0, vz0 : array_like
        Velocity at ``y = y0``, ft/s (``vy0 < 0``).
    ax, ay, az : array_like
        Constant acceleration, ft/s^2.
    y0 : float
        Where the velocity is given, ft (Statcast: 50).
    y_plate : float
        The plane of the crossing, ft (default: the front of the plate, 17/12 ft).

    Returns
    -------
    speed : ndarray
        ``|v|`` at the crossing, mph.
    vertical_approach_angle, horizontal_approach_angle : ndarray
        deg, mcbat's conventions (module docstring). NaN where an input is NaN, where the
        ball does not reach the plane (``vy0^2 < 2 ay (y0 - y_plate)``: decelerating to
        rest first) or where ``vy0 >= 0`` (not moving towards the plate).
    """
    vx0, vy0, vz0, ax, ay, az = (np.asarray(v, dtype=float)
                                 for v in (vx0, vy0, vz0, ax, ay, az))
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = vy0 * vy0 - 2.0 * ay * (y0 - y_plate)
        vy = -np.sqrt(np.where(disc >= 0.0, disc, np.nan))
        vy = np.where(vy0 < 0.0, vy, np.nan)
        # t = (vy - vy0)/ay, written without the division that fails for ay = 0: since
        # vy^2 - vy0^2 = -2 ay (y0 - y_plate), t = 2 (y0 - y_plate) / -(vy + vy0).
        t = 2.0 * (y0 - y_plate) / -(vy + vy0)
        vx = vx0 + ax * t
        vz = vz0 + az * t
        speed = np.sqrt(vx * vx + vy * vy + vz * vz) / FT_S_PER_MPH
        vertical = np.degrees(np.arctan2(vz, np.hypot(vx, vy)))
        horizontal = np.degrees(np.arctan2(vx, -vy))
    return speed, vertical, horizontal


def spray_angle(hc_x: ArrayLike, hc_y: ArrayLike) -> NDArray[np.float64]:
    """The batted ball's horizontal direction from Statcast's hit coordinates, deg.

    ``atan2(hc_x - 125.42, 198.27 - hc_y)``: 0 towards centre field, positive towards
    the first-base (right-field) side, as mcbat's ``spray_angle = atan2(v_x, v_y)``
    (``hc_y`` grows towards home plate, hence the reversed difference). It is the
    direction of the point where the ball was first fielded (or landed), seen from home
    plate, not the launch direction measured at the bat: the two differ by the ball's
    sideways curve in flight. For fair balls (``hc_y < 198.27``) it equals
    ``atan((hc_x - 125.42) / (198.27 - hc_y))``; ``atan2`` also keeps balls fielded behind
    the plate on their own side. NaN where either coordinate is NaN.
    """
    hc_x = np.asarray(hc_x, dtype=float)
    hc_y = np.asarray(hc_y, dtype=float)
    x0, y0 = HOME_PLATE_HC
    return np.degrees(np.arctan2(hc_x - x0, y0 - hc_y))
