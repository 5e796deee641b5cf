"""What the layers above read of the kernels besides calling them: the names of their
input and output rows, their status codes, the ranges the impact solver works in, the
flight's parameters (all defined in ``mcbat.core``;
SI units throughout).
"""

from __future__ import annotations

from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS
from mcbat.core.cabo2012.impact import (
    IMPACT_FIELDS,
    INERTIA_RANGE,
    LENGTH_RANGE,
    MASS_RANGE,
    MAX_AXIAL,
    MAX_MU,
    MAX_SPEED,
    MAX_SPIN,
)
from mcbat.core.flight import DEFAULT_TOLERANCE as FLIGHT_TOLERANCE
from mcbat.core.flight import (
    FLIGHT_FIELDS,
    GRAVITY,
    MODELS,
    Aero,
    Flight,
    FlightParams,
    FlightStatus,
    air_density,
    pack_params,
)
from mcbat.core.flight.trajectory import MAX_STEPS as FLIGHT_MAX_STEPS
from mcbat.core.swing import (
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    SWEET_SPOT_FROM_BARREL_END,
    bat_frame_columns,
    incoming_state,
)

__all__ = ["FLIGHT_FIELDS", "FLIGHT_MAX_STEPS", "FLIGHT_TOLERANCE", "GAME_INPUT_FIELDS",
           "GAME_OUTPUT_FIELDS", "GRAVITY", "IMPACT_FIELDS", "INERTIA_RANGE", "INPUT_FIELDS",
           "LENGTH_RANGE", "MASS_RANGE", "MAX_AXIAL", "MAX_MU", "MAX_SPEED", "MAX_SPIN",
           "MODELS", "OUTPUT_FIELDS", "SWEET_SPOT_FROM_BARREL_END", "Aero", "Flight",
           "FlightParams", "FlightStatus", "air_density", "bat_frame_columns",
           "incoming_state", "pack_params"]
