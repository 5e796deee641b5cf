"""Derived quantities of a solved ball and their inverse, in one place: the bat frame's
exit speed, scattering angle and spins (``derive``), the batted ball in the field's
conventions (``derive_game``: Statcast's launch speed, launch and spray angles, and the
spin's backspin, sidespin and gyrospin components), and the field-frame velocity and spin
of given launch numbers (``launch_vectors``, the inverse of ``derive_game``).

Plain numpy on scalars or arrays, so that the datasets, the single-case API, the fits,
the spin inference and the flight share one definition of each quantity
(``docs/batting.md`` states the conventions).
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mcbat.core.units import M_S_PER_MPH, RPM_PER_RAD_S

__all__ = ["derive", "derive_game", "launch_vectors"]


def derive(ball_velocity: Sequence[ArrayLike], ball_spin: Sequence[ArrayLike],
           names: Collection[str] | None = None) -> dict[str, Any]:
    """The derived columns from the outgoing ball's velocity and spin (lab frame).

    Parameters
    ----------
    ball_velocity, ball_spin : sequence of 3 floats or 3 arrays
        ``(v_x, v_y, v_z)`` in m/s and ``(w_x, w_y, w_z)`` in rad/s.
    names : collection of str, optional
        Compute only these of the four below (a summary-only run needs only the
        columns it summarises); default all.

    Returns
    -------
    dict
        ``exit_speed`` (m/s), ``scattering_angle`` (deg, ``atan2(v_y, v_x)``: 0 is
        straight back along ``+x``), ``spin_axial`` (rad/s, about the bat axis ``z``) and
        ``spin`` (rad/s, the magnitude); floats for float inputs, else arrays.
    """
    vx, vy, vz = (np.asarray(c, np.float64) for c in ball_velocity)
    wx, wy, wz = (np.asarray(c, np.float64) for c in ball_spin)
    formulas: dict[str, Callable[[], Any]] = {
        "exit_speed": lambda: np.sqrt(vx * vx + vy * vy + vz * vz),
        "scattering_angle": lambda: np.degrees(np.arctan2(vy, vx)),
        "spin_axial": lambda: wz,
        "spin": lambda: np.sqrt(wx * wx + wy * wy + wz * wz),
    }
    out = {name: formula() for name, formula in formulas.items()
           if names is None or name in names}
    if np.ndim(vx) == 0:
        return {name: float(value) for name, value in out.items()}
    return out


def derive_game(ball_velocity: Sequence[ArrayLike],
                ball_spin: Sequence[ArrayLike]) -> dict[str, Any]:
    """The batted ball in the field's conventions, from its field-frame velocity and spin.

    Parameters
    ----------
    ball_velocity, ball_spin : sequence of 3 floats or 3 arrays
        Field frame (``x`` to first base, ``y`` to the pitcher, ``z`` up), m/s and rad/s.

    Returns
    -------
    dict
        ``launch_speed`` (mph), ``launch_angle`` (deg, elevation), ``spray_angle`` (deg,
        ``atan2(v_x, v_y)``, positive towards right field), ``spin_rate`` (rpm),
        ``backspin`` (``w . b``, ``b = unit(v x z)``), ``sidespin`` (``w . s``,
        ``s = b x unit(v)``; positive curves towards left field), ``gyrospin``
        (``w . unit(v)``), all rpm (docs/batting.md).
    """
    vx, vy, vz = (np.asarray(c, np.float64) for c in ball_velocity)
    wx, wy, wz = (np.asarray(c, np.float64) for c in ball_spin)
    speed = np.sqrt(vx * vx + vy * vy + vz * vz)
    horizontal = np.hypot(vx, vy)
    with np.errstate(invalid="ignore", divide="ignore"):
        # b = unit(v x z) = (v_y, -v_x, 0)/|v_h|; s = b x unit(v); unit(v) = v/|v|
        bx, by = vy / horizontal, -vx / horizontal
        ux, uy, uz = vx / speed, vy / speed, vz / speed
        sx, sy, sz = by * uz, -bx * uz, bx * uy - by * ux
        out = {
            "launch_speed": speed / M_S_PER_MPH,
            "launch_angle": np.degrees(np.arctan2(vz, horizontal)),
            "spray_angle": np.degrees(np.arctan2(vx, vy)),
            "spin_rate": np.sqrt(wx * wx + wy * wy + wz * wz) * RPM_PER_RAD_S,
            "backspin": (wx * bx + wy * by) * RPM_PER_RAD_S,
            "sidespin": (wx * sx + wy * sy + wz * sz) * RPM_PER_RAD_S,
            "gyrospin": (wx * ux + wy * uy + wz * uz) * RPM_PER_RAD_S,
        }
    if np.ndim(vx) == 0:
        return {name: float(value) for name, value in out.items()}
    return out


def launch_vectors(launch_speed: ArrayLike, launch_angle: ArrayLike, spray_angle: ArrayLike,
                   backspin: Any, sidespin: Any, gyrospin: Any
                   ) -> tuple[tuple[Any, Any, Any], tuple[Any, Any, Any]]:
    """Field-frame velocity (m/s) and spin (rad/s) from Statcast-style launch numbers (SI:
    m/s, rad, rad/s; scalars or arrays): the inverse of ``derive_game`` (``b = unit(v x z)``,
    ``s = b x unit(v)``)."""
    la, sp = np.asarray(launch_angle, float), np.asarray(spray_angle, float)
    ux, uy, uz = np.cos(la) * np.sin(sp), np.cos(la) * np.cos(sp), np.sin(la)
    bx, by = np.cos(sp), -np.sin(sp)  # unit(u x z) = (u_y, -u_x, 0) / cos(la)
    sx, sy, sz = by * uz, -bx * uz, bx * uy - by * ux
    v = tuple(np.asarray(launch_speed, float) * c for c in (ux, uy, uz))
    w = (backspin * bx + sidespin * sx + gyrospin * ux,
         backspin * by + sidespin * sy + gyrospin * uy,
         sidespin * sz + gyrospin * uz)
    return v, w
