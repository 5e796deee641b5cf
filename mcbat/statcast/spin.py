"""Nathan's average spin model of a batted ball, as his trajectory calculator uses it.

For a right-handed batter (rpm; ``LA`` the launch angle and ``phi`` the spray angle, deg,
positive towards right field)::

    backspin = -763 + 120 LA + 21 phi
    sidespin = -849 - 94 phi

``backspin`` and ``sidespin`` are the project's (``docs/batting.md``): backspin along
``b = unit(v x z)``, sidespin along ``s = b x unit(v)``, positive sidespin curving the ball
towards left field. With that sign, the model's pulled balls (``phi < 0``) hook towards
the left-field line and its opposite-field balls (``phi > 0``) slice towards the
right-field line, as a right-handed batter's balls are seen to do.

A left-handed batter is the mirror image of a right-handed one in ``x`` (the plane
through home plate and second base). The mirror turns a spray angle ``phi`` into ``-phi``;
the spin is an axial vector, so the mirror keeps the backspin (``omega . (v x z)`` is
unchanged) and reverses the sidespin. Hence, for a left-handed batter with spray angle
``phi``::

    backspin = -763 + 120 LA - 21 phi
    sidespin = +849 - 94 phi

(his pulled balls, ``phi > 0``, hook towards the right-field line: ``sidespin < 0``). The
model is an average over balls: real balls scatter about it by hundreds of rpm.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["HANDEDNESS", "nathan_average_spin"]

#: Batter's side -> sign of the mirror in ``x`` (+1 right-handed, -1 left-handed).
HANDEDNESS = {"R": 1.0, "L": -1.0}


def nathan_average_spin(launch_angle: ArrayLike, spray_angle: ArrayLike, handedness: ArrayLike
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(backspin, sidespin)`` in rpm of Nathan's average model (module docstring).

    Parameters
    ----------
    launch_angle, spray_angle : array_like
        deg (spray positive towards right field).
    handedness : array_like of str
        ``"R"`` or ``"L"`` per ball (the batter's side, Statcast's ``stand``).

    Raises
    ------
    ValueError
        If a handedness is neither ``"R"`` nor ``"L"``.
    """
    la = np.asarray(launch_angle, float)
    side = np.asarray(handedness, dtype=object)
    mirror = np.array([HANDEDNESS.get(h, np.nan) for h in side.ravel()]).reshape(side.shape)
    if np.isnan(mirror).any():
        bad = side.ravel()[np.isnan(mirror.ravel())][0]
        raise ValueError(f"handedness must be 'R' or 'L', got {bad!r}")
    phi = mirror * np.asarray(spray_angle, float)  # the right-handed batter's spray angle
    backspin = -763.0 + 120.0 * la + 21.0 * phi
    sidespin = mirror * (-849.0 - 94.0 * phi)
    return backspin, sidespin
