"""The flight of the scan's batted balls: ``mcbat.solving.fly_balls`` with the calculator's
standard conditions (70 degF, 29.92 inHg, 50 % RH, sea level), Nathan's aerodynamics and
spin decay, from the calculator's launch point (0, 2, 3) ft, for the game studies' ball."""

import numpy as np

from mcbat.bodies import ball_preset
from mcbat.core.units import M_PER_FT
from mcbat.solving import FLIGHT_FIELDS, FlightStatus, fly_balls
from mcbat.study.flight import FlightSettings

__all__ = ["BALL", "FLIGHT_SETTINGS", "SETTINGS", "fly"]

#: The flight settings of the reproduction (the defaults).
SETTINGS = FlightSettings()
#: The ball (the game studies' preset).
BALL = ball_preset("baseball")
#: The settings as written into the summary.
FLIGHT_SETTINGS = {**SETTINGS.config(), "ball_mass_kg": BALL.mass,
                   "ball_radius_m": BALL.radius}



def fly(v, w, settings=SETTINGS):
    """Carry balls launched with field-frame velocity ``v`` (m/s) and spin ``w`` (rad/s),
    ``float64[3, n]``, with ``settings`` (a ``mcbat.study.flight.FlightSettings``;
    default: the reproduction's); returns ``hit_distance``, ``landing_x``, ``landing_y``,
    ``apex`` (ft) and ``hang_time`` (s), NaN where a flight failed."""
    v = np.ascontiguousarray(v, np.float64)
    w = np.ascontiguousarray(w, np.float64)
    return _carry(*fly_balls(settings.params(BALL.mass, BALL.radius), settings.start, v, w))


def _carry(out, status):
    """The landing of balls flown (``mcbat.solving.FlightSolution``: ``out``, SI, and
    ``status``): ``hit_distance``, ``landing_x``, ``landing_y``, ``apex`` (ft) and
    ``hang_time`` (s), NaN where a flight failed."""
    row = {name: i for i, name in enumerate(FLIGHT_FIELDS)}
    bad = status != FlightStatus.OK
    result = {name: np.where(bad, np.nan, out[row[name]] / M_PER_FT)
              for name in ("hit_distance", "landing_x", "landing_y", "apex")}
    result["hang_time"] = np.where(bad, np.nan, out[row["hang_time"]])
    return result
