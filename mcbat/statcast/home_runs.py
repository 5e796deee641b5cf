"""Would it have left the park? A batted ball flown to a park's outfield fence.

The call: the ball is flown (each in its own air) until its horizontal distance from home
plate reaches the fence's distance along the direction in which it is travelling there;
it is a home run when it passes that point higher than the fence
(``mcbat.study.flight.heights_at_distance``). A ball that meets the wall while still
rising, a line drive, is no home run even if it would have carried farther. The fence's
distance depends on the spray angle at the crossing, which the ball's curve moves from its
launch spray (a pulled or sliced fly ball by 10-15 deg), so the crossing is found by
iteration: at the fence of the direction the ball comes down in, then at the fence of the
spray where the ball crossed (three times; a fence the ball does not reach sends the
next guess back to where it comes down). Fences: ``parks.fence`` (one configuration per
park; ``docs/parks-and-weather.md``).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import special

from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL, Ball
from mcbat.core.units import M_PER_FT, M_S_PER_MPH, RAD_PER_DEG, RAD_S_PER_RPM
from mcbat.solving import FlightStatus
from mcbat.statcast import parks
from mcbat.study.flight import FlightSettings, fly_launches, heights_at_distance

__all__ = ["home_run_call"]

_Floats = NDArray[np.float64]



def home_run_call(launch_speed: ArrayLike, launch_angle: ArrayLike, spray_angle: ArrayLike,
                  backspin: ArrayLike, sidespin: ArrayLike, park: ArrayLike, *,
                  game_date: ArrayLike | None = None, settings: FlightSettings | None = None,
                  ball: Ball | None = None, per_ball: Mapping[str, ArrayLike] | None = None,
                  scatter_ft: ArrayLike | None = None) -> pd.DataFrame:
    """Whether each ball clears its park's fence.

    Parameters
    ----------
    launch_speed, launch_angle, spray_angle : array_like
        Statcast's (mph, deg, deg; spray ``atan2(x, y)``, > 0 towards right field).
    backspin, sidespin : array_like
        rpm (``docs/flight.md``).
    park : str or array_like of str
        ``park_id`` of ``mcbat.statcast.parks.park_of``, one or one per ball.
    game_date : array_like, optional
        Each ball's date: the fences standing at its park that day
        (``mcbat.statcast.parks.fence``); without it, the fences standing now.
    settings : FlightSettings, optional
        The flight (default: Nathan's model in standard air).
    ball : mcbat.bodies.Ball, optional
        Default: the regulation baseball.
    per_ball : mapping, optional
        Per-ball flight settings (SI; ``mcbat.study.flight.PER_BALL``): the park's
        elevation, the game's air, a season's drag.

    Returns
    -------
    pandas.DataFrame
        Per ball: ``fence_distance`` and ``fence_height`` (ft) where it crosses,
        ``height_at_fence`` (ft; NaN: down before the fence), ``clearance`` (ft, height
        above the fence), ``home_run`` (nullable boolean: NA where the fence's height is
        not known), and with ``scatter_ft`` the ``margin`` (ft: how much farther than the
        fence the descending ball passes the fence's height; a ball that meets the wall
        below its top, rising or not, is short by at least that height shortfall) and
        ``home_run_probability`` (``Phi(margin / scatter_ft)``).
    """
    settings = FlightSettings() if settings is None else settings
    ball = BALL_PRESETS[DEFAULT_BALL] if ball is None else ball
    speed = np.atleast_1d(np.asarray(launch_speed, float))
    n = speed.size
    spray = np.broadcast_to(np.asarray(spray_angle, float), (n,))
    ids = np.broadcast_to(np.asarray(park, dtype=object), (n,))
    dates = None if game_date is None else np.broadcast_to(
        np.asarray(game_date, dtype="datetime64[D]"), (n,))
    def each(values: ArrayLike) -> NDArray[np.float64]:
        return np.broadcast_to(np.asarray(values, float), (n,))

    launch = (speed * M_S_PER_MPH, each(launch_angle) * RAD_PER_DEG, spray * RAD_PER_DEG,
              each(backspin) * RAD_S_PER_RPM, each(sidespin) * RAD_S_PER_RPM)
    # A home run meets the fence near the end of its flight, so the first guess of where
    # is where it comes down: its curve can take it 10-15 deg from its launch direction,
    # and from the launch direction's fence (the deep alley instead of the line) it would
    # seem to come down short. A guess the ball does not reach falls back on it too.
    landing = _landing_spray(settings, ball, launch, per_ball, spray)
    crossing = landing
    for _ in range(3):
        distance, height = parks.fence(ids, crossing, dates)
        z, phi = heights_at_distance(settings, ball.mass, ball.radius, distance * M_PER_FT,
                                     *launch, per_ball=per_ball)
        crossing = np.where(np.isfinite(phi), np.degrees(phi), landing)
    distance, height = parks.fence(ids, crossing, dates)
    z, _ = heights_at_distance(settings, ball.mass, ball.radius, distance * M_PER_FT, *launch,
                               per_ball=per_ball)
    z_ft = z / M_PER_FT
    clearance = z_ft - height
    known = np.isfinite(height) & np.isfinite(distance)
    call = pd.array(np.where(known, np.isfinite(clearance) & (clearance > 0), False),
                    dtype="boolean")
    call[~known] = pd.NA
    out = pd.DataFrame({"fence_distance": distance, "fence_height": height,
                        "height_at_fence": z_ft, "clearance": clearance, "home_run": call})
    out.attrs["units"] = {"fence_distance": "ft", "fence_height": "ft",
                          "height_at_fence": "ft", "clearance": "ft", "home_run": "bool"}
    if scatter_ft is not None:
        margin = _margin(settings, ball, launch, per_ball, distance, height, clearance)
        out["margin"] = margin
        out["home_run_probability"] = np.where(
            known, special.ndtr(np.nan_to_num(margin, nan=-1e9)
                                / np.broadcast_to(np.asarray(scatter_ft, float), (n,))),
            np.nan)
        out.attrs["units"].update(margin="ft", home_run_probability="1")
    return out


def _landing_spray(settings: FlightSettings, ball: Ball,
                   launch: tuple[_Floats, _Floats, _Floats, _Floats, _Floats],
                   per_ball: Mapping[str, ArrayLike] | None, spray: _Floats) -> _Floats:
    """The direction (deg, as ``spray``) in which each ball comes down; its launch
    ``spray`` where it does not land."""
    out, status = fly_launches(settings, ball.mass, ball.radius, *launch, per_ball=per_ball)
    landed = status == FlightStatus.OK
    return np.where(landed, np.degrees(np.arctan2(out["landing_x"], out["landing_y"])),
                    spray)


def _margin(settings: FlightSettings, ball: Ball,
            launch: tuple[_Floats, _Floats, _Floats, _Floats, _Floats],
            per_ball: Mapping[str, ArrayLike] | None, distance: _Floats, height: _Floats,
            clearance: _Floats) -> _Floats:
    """How much farther than the fence each ball passes the fence's height on its way down
    (ft); for a ball below the wall's top where it meets it, at most minus the height it
    lacks (a line drive still rising at the wall is short however far it would carry)."""
    per = {} if per_ball is None else dict(per_ball)
    per["landing_height"] = np.nan_to_num(height, nan=0.0) * M_PER_FT
    out, status = fly_launches(settings, ball.mass, ball.radius, *launch, per_ball=per)
    down_at = np.where(status == FlightStatus.OK, out["hit_distance"] / M_PER_FT, -np.inf)
    margin = down_at - distance
    below = np.isfinite(clearance) & (clearance <= 0)
    return np.where(below, np.minimum(margin, clearance), margin)
