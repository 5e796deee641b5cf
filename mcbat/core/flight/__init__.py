"""Batted-ball flight in the field frame (Nathan's trajectory calculator's model and
others): air density, aerodynamic coefficients, the integrator (``README.md``)."""

from mcbat.core.flight.aero import CONSTANT, MODELS, NATHAN, SAWICKI2003, Aero
from mcbat.core.flight.atmosphere import air_density
from mcbat.core.flight.trajectory import (
    DEFAULT_TOLERANCE,
    FLIGHT_FIELDS,
    GRAVITY,
    Flight,
    FlightParams,
    FlightStatus,
    allocate_flight_outputs,
    fly,
    fly_batch,
    fly_batch_each,
    height_at_distance,
    height_at_distance_batch,
    pack_params,
)

__all__ = ["CONSTANT", "DEFAULT_TOLERANCE", "FLIGHT_FIELDS", "GRAVITY", "MODELS", "NATHAN",
           "SAWICKI2003", "Aero", "Flight", "FlightParams", "FlightStatus", "air_density",
           "allocate_flight_outputs", "fly", "fly_batch", "fly_batch_each",
           "height_at_distance", "height_at_distance_batch", "pack_params"]
