"""What the layers above read of the kernels besides calling them: the names of their
input and output rows, their status codes, the ranges the impact solver works in and the
flight's parameters (all defined in ``mcbat.core``; SI units throughout).
"""

from __future__ import annotations

from mcbat.core import batch as impact_batch
from mcbat.core.cabo2012 import impact
from mcbat.core.flight import aero as flight_aero
from mcbat.core.flight import trajectory
from mcbat.core.flight.atmosphere import air_density
from mcbat.core.flight.trajectory import pack_params
from mcbat.core.swing import frames, game
from mcbat.core.swing.game import bat_frame_columns, incoming_state

__all__ = ["FLIGHT_FIELDS", "FLIGHT_MAX_STEPS", "FLIGHT_TOLERANCE", "GAME_INPUT_FIELDS",
           "GAME_OUTPUT_FIELDS", "GRAVITY", "IMPACT_FIELDS", "INERTIA_RANGE", "INPUT_FIELDS",
           "LENGTH_RANGE", "MASS_RANGE", "MAX_AXIAL", "MAX_MU", "MAX_SPEED", "MAX_SPIN",
           "MODELS", "OUTPUT_FIELDS", "SWEET_SPOT_FROM_BARREL_END", "Aero", "Flight",
           "FlightParams", "FlightStatus", "air_density", "bat_frame_columns",
           "incoming_state", "pack_params"]

# The bat-frame impact: rows of solve_impacts' inputs and outputs, the single impact's
# fields, and the ranges the solver works in (kg, m, kg m^2, m/s, rad/s).
INPUT_FIELDS = impact_batch.INPUT_FIELDS
OUTPUT_FIELDS = impact_batch.OUTPUT_FIELDS
IMPACT_FIELDS = impact.IMPACT_FIELDS
MASS_RANGE = impact.MASS_RANGE
LENGTH_RANGE = impact.LENGTH_RANGE
INERTIA_RANGE = impact.INERTIA_RANGE
MAX_AXIAL = impact.MAX_AXIAL
MAX_SPEED = impact.MAX_SPEED
MAX_SPIN = impact.MAX_SPIN
MAX_MU = impact.MAX_MU

# The game: rows of solve_games' inputs and outputs, the bat's sweet spot (m from the
# barrel end); bat_frame_columns (the bat-frame columns of game rows) and incoming_state
# (the incoming ball and bat of one) are imported above.
GAME_INPUT_FIELDS = game.GAME_INPUT_FIELDS
GAME_OUTPUT_FIELDS = game.GAME_OUTPUT_FIELDS
SWEET_SPOT_FROM_BARREL_END = frames.SWEET_SPOT_FROM_BARREL_END

# The flight: rows of fly_balls' outputs, its status codes, its parameters (packed for
# the batch kernels by pack_params, above), the aerodynamic models, gravity (m/s^2) and
# the integrator's default tolerance and step budget; air_density (kg/m^3) is above.
FLIGHT_FIELDS = trajectory.FLIGHT_FIELDS
FlightStatus = trajectory.FlightStatus
Flight = trajectory.Flight
FlightParams = trajectory.FlightParams
GRAVITY = trajectory.GRAVITY
FLIGHT_TOLERANCE = trajectory.DEFAULT_TOLERANCE
FLIGHT_MAX_STEPS = trajectory.MAX_STEPS
MODELS = flight_aero.MODELS
Aero = flight_aero.Aero
