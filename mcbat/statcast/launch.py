"""The direction a batted ball left the bat in, from where it came down.

Savant's spray angle (from the hit coordinates, :func:`mcbat.statcast.kinematics.spray_angle`)
is the direction of the point where the ball landed or was fielded. A ball with sidespin
curves on its way: with Nathan's average spin model (:mod:`mcbat.statcast.spin`) a pulled
ball hooks towards the line by several degrees. Flying a ball from its landing direction as
if it were its launch direction would count the curve twice. :func:`launch_spray` finds the
launch direction, and Nathan's spin for it, whose flight comes down along the measured
spray angle.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL, Ball
from mcbat.core.units import M_S_PER_MPH, RAD_PER_DEG, RAD_S_PER_RPM
from mcbat.solving import FlightStatus
from mcbat.statcast.spin import nathan_average_spin
from mcbat.study.flight import FlightSettings, fly_launches

__all__ = ["launch_spray"]



def launch_spray(launch_speed: ArrayLike, launch_angle: ArrayLike, spray_angle: ArrayLike,
                 handedness: ArrayLike, *, per_ball: Mapping[str, ArrayLike] | None = None,
                 settings: FlightSettings | None = None, ball: Ball | None = None,
                 iterations: int = 3
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Launch spray angle (deg) and Nathan's spin for it (rpm) of each ball, such that its
    flight comes down along its measured ``spray_angle``.

    Newton's iteration on the landing direction (three steps bring the landing within
    hundredths of a degree); a ball that does not land keeps its measured angle.

    Parameters
    ----------
    launch_speed, launch_angle, spray_angle : array_like
        mph, deg, deg (Statcast's; spray ``atan2(x, y)``, > 0 towards right field).
    handedness : array_like of str
        The batter's side, ``R`` or ``L``.
    per_ball : mapping, optional
        Per-ball flight settings (SI; :data:`mcbat.study.flight.PER_BALL`): each ball's air
        and drag.
    settings : FlightSettings, optional
        Default: Nathan's model, standard air.
    ball : mcbat.bodies.Ball, optional
        Default: the regulation baseball.

    Returns
    -------
    spray, backspin, sidespin : ndarray
        deg, rpm, rpm.
    """
    settings = FlightSettings() if settings is None else settings
    ball = BALL_PRESETS[DEFAULT_BALL] if ball is None else ball
    measured = np.asarray(spray_angle, float)
    angle = np.asarray(launch_angle, float)
    speed = np.asarray(launch_speed, float) * M_S_PER_MPH
    hand = np.asarray(handedness, dtype=object)
    tripled = None if per_ball is None else {
        k: np.tile(np.broadcast_to(np.asarray(v, float), measured.shape), 3)
        for k, v in per_ball.items()}
    spray = measured.copy()
    for _ in range(iterations):
        # Newton's step on the landing direction, its slope from a central difference of
        # one degree (the curve depends on the launch direction through Nathan's
        # sidespin; central, so that a left-handed batter is the exact mirror image)
        n = measured.size
        trial = np.concatenate([spray, spray - 0.5, spray + 0.5])
        landed = _landing(np.tile(speed, 3), np.tile(angle, 3), trial, np.tile(hand, 3),
                          tripled, settings, ball)
        here, slope = landed[:n], landed[2 * n:] - landed[n:2 * n]
        ok = np.isfinite(here) & np.isfinite(slope) & (slope > 0.1)
        spray = np.where(ok, spray + (measured - here) / np.where(ok, slope, 1.0), measured)
    back, side = (np.asarray(x, float) for x in nathan_average_spin(angle, spray, handedness))
    return spray, back, side


def _landing(speed: NDArray[np.float64], angle: NDArray[np.float64],
             spray: NDArray[np.float64], handedness: NDArray[Any],
             per_ball: dict[str, NDArray[np.float64]] | None, settings: FlightSettings,
             ball: Ball) -> NDArray[np.float64]:
    """Landing direction (deg) of balls flown from ``spray`` with Nathan's spin for it."""
    back, side = (np.asarray(x, float) for x in nathan_average_spin(angle, spray,
                                                                      handedness))
    out, status = fly_launches(settings, ball.mass, ball.radius, speed, angle * RAD_PER_DEG,
                               spray * RAD_PER_DEG, back * RAD_S_PER_RPM, side * RAD_S_PER_RPM,
                               per_ball=per_ball)
    landed = status == FlightStatus.OK
    return np.where(landed, np.degrees(np.arctan2(out["landing_x"], out["landing_y"])), np.nan)
