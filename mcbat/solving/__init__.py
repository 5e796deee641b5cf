"""The solving layer: the one place above ``mcbat.core`` that calls the jitted kernels.

Studies, the single-case API, the engines, the fits, the spin inference, the Statcast
replays and the papers' reproductions solve impacts, game situations and flights through
the functions here, each taking validated arrays (SI) and one ``SolverSettings`` and
returning a named tuple of arrays with a status per row:

- ``solve_impacts`` (bat-frame impacts), ``solve_games`` (game situations),
  ``fly_balls`` (one air), ``fly_balls_each`` (each ball its own air),
  ``heights_at_distance``, ``solve_and_fly`` (a game's batted balls flown);
  ``mcbat.solving.inference.infer_contacts`` (the contact inference, with its settings
  and codes);
- ``solve_one_impact``, ``impact_history``, ``fly_one``, ``fly_sampled``: single cases.

What else the layers above read of the kernels (row names, status codes, ranges, the
flight's parameters) is re-exported from ``mcbat.solving.names``; an import-linter
contract keeps the kernel modules behind this package (``docs/contributing.md``).
"""

from mcbat.solving.batch import (
    FlightSolution,
    GameFlight,
    GameSolution,
    ImpactSolution,
    allocate_flights,
    allocate_games,
    allocate_impacts,
    batch_kernels,
    batted_ball_vectors,
    fly_balls,
    fly_balls_each,
    heights_at_distance,
    solve_and_fly,
    solve_games,
    solve_impacts,
)
from mcbat.solving.names import (
    FLIGHT_FIELDS,
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    INPUT_FIELDS,
    OUTPUT_FIELDS,
    FlightParams,
    FlightStatus,
)
from mcbat.solving.settings import (
    DEFAULT_MAX_STEPS,
    DEFAULT_STEPS,
    DEFAULT_TOLERANCE,
    SolverSettings,
)
from mcbat.solving.single import fly_one, fly_sampled, impact_history, solve_one_impact

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_STEPS", "DEFAULT_TOLERANCE", "FLIGHT_FIELDS",
           "GAME_INPUT_FIELDS", "GAME_OUTPUT_FIELDS", "INPUT_FIELDS", "OUTPUT_FIELDS",
           "FlightParams", "FlightSolution", "FlightStatus", "GameFlight", "GameSolution",
           "ImpactSolution", "SolverSettings", "allocate_flights", "allocate_games",
           "allocate_impacts", "batch_kernels", "batted_ball_vectors", "fly_balls",
           "fly_balls_each", "fly_one", "fly_sampled", "heights_at_distance",
           "impact_history", "solve_and_fly", "solve_games", "solve_impacts",
           "solve_one_impact"]
