"""Batches of impacts, game situations and flights: the calls of the jitted batch kernels.

Every function takes validated, C-contiguous ``float64`` arrays (one column per row of
the batch, SI units), and for the impact solver one ``SolverSettings``; it returns a small
named tuple of arrays with an ``int8`` status per row (0 ok; the impact's codes are
``mcbat.core.status``, the flight's ``FlightStatus``). Nothing is checked here and nothing
raises on a bad row: the layers above check their input and read the status. The output
arrays are fresh unless ``into`` gives the ones to write to (a fit solving the same shape
many times allocates them once, ``allocate_*``).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from mcbat.core import batch as impact_kernel
from mcbat.core.flight import trajectory as flight_kernel
from mcbat.core.jit import await_group
from mcbat.core.swing import game as game_kernel
from mcbat.solving.names import GAME_OUTPUT_FIELDS, FlightParams
from mcbat.solving.settings import SolverSettings

__all__ = ["FlightSolution", "GameFlight", "GameSolution", "ImpactSolution",
           "allocate_flights", "allocate_games", "allocate_impacts", "batch_kernels",
           "batted_ball_vectors", "fly_balls", "fly_balls_each", "heights_at_distance",
           "solve_and_fly", "solve_games", "solve_impacts"]

Floats = NDArray[np.float64]
Codes = NDArray[np.int8]

_V = tuple(GAME_OUTPUT_FIELDS.index(f"field_ball_v{c}") for c in "xyz")
_W = tuple(GAME_OUTPUT_FIELDS.index(f"field_ball_w{c}") for c in "xyz")


class ImpactSolution(NamedTuple):
    """Bat-frame impacts solved (``n`` rows)."""

    #: ``float64[len(OUTPUT_FIELDS), n]``: velocities (m/s), spins (rad/s), impulses
    #: (kg m/s), works and energies (J), as ``mcbat.solving.OUTPUT_FIELDS``.
    out: Floats
    #: ``int8[n]``: 0 ok, else a code of ``mcbat.core.status``.
    status: Codes
    #: ``int8[n]``: sliding or stuck at separation (``mcbat.core.status.EndState``).
    end_state: Codes


class GameSolution(NamedTuple):
    """Game situations solved (``n`` rows)."""

    #: ``float64[len(FRAME_FIELDS), n]``: the bat-frame inputs the game gave (SI).
    frame: Floats
    #: ``float64[len(OUTPUT_FIELDS), n]``: the bat-frame impact's outputs (SI).
    out: Floats
    #: ``float64[len(GAME_OUTPUT_FIELDS), n]``: the batted ball in the field frame (m/s,
    #: rad/s) and the collision efficiency.
    game_out: Floats
    #: ``int8[n]``: 0 ok, else a code of ``mcbat.core.status``.
    status: Codes
    #: ``int8[n]``: sliding or stuck at separation.
    end_state: Codes


class FlightSolution(NamedTuple):
    """Balls flown (``n`` rows)."""

    #: ``float64[len(FLIGHT_FIELDS), n]``: distance, landing point (m), hang time (s),
    #: apex (m), ... as ``mcbat.solving.FLIGHT_FIELDS``.
    out: Floats
    #: ``int8[n]``: 0 ok, else a code of ``FlightStatus``.
    status: Codes


class GameFlight(NamedTuple):
    """Game situations solved and their batted balls flown (``n`` rows)."""

    game: GameSolution
    #: ``float64[3, n]``: the batted ball's launch velocity (m/s, field frame).
    velocity: Floats
    #: ``float64[3, n]``: its spin (rad/s, field frame).
    spin: Floats
    #: The flight, from the launch point ``start``.
    flight: FlightSolution


def allocate_impacts(n: int) -> ImpactSolution:
    """Empty outputs of ``solve_impacts`` for ``n`` rows."""
    return ImpactSolution(*impact_kernel.allocate_outputs(n))


def allocate_games(n: int) -> GameSolution:
    """Empty outputs of ``solve_games`` for ``n`` rows."""
    return GameSolution(*game_kernel.allocate_game_outputs(n))


def allocate_flights(n: int) -> FlightSolution:
    """Empty outputs of ``fly_balls`` for ``n`` balls."""
    return FlightSolution(*flight_kernel.allocate_flight_outputs(n))


def solve_impacts(inputs: Floats, settings: SolverSettings,
                  into: ImpactSolution | None = None) -> ImpactSolution:
    """Solve bat-frame impacts in parallel (``mcbat.core.batch.solve_batch``).

    Parameters
    ----------
    inputs : ndarray of float64, shape (len(INPUT_FIELDS), n)
        One impact per column, rows ``mcbat.solving.INPUT_FIELDS`` (SI: kg, m, kg m^2,
        rad, m/s, rad/s; ``mu``, ``e``, ``e_x`` dimensionless).
    settings : SolverSettings
        The solver's accuracy.
    into : ImpactSolution, optional
        Outputs of ``n`` rows to write to (``allocate_impacts``); fresh ones by default.

    Returns
    -------
    ImpactSolution
        ``out`` (SI), ``status`` and ``end_state`` per impact.
    """
    result = allocate_impacts(inputs.shape[1]) if into is None else into
    await_group("bat_frame")
    impact_kernel.solve_batch(inputs, settings.steps, settings.tolerance, settings.max_steps,
                              result.out, result.status, result.end_state)
    return result


def solve_games(inputs: Floats, settings: SolverSettings,
                into: GameSolution | None = None) -> GameSolution:
    """Solve game situations in parallel (``mcbat.core.swing.solve_game_batch``).

    Parameters
    ----------
    inputs : ndarray of float64, shape (len(GAME_INPUT_FIELDS), n)
        One pitch and swing per column, rows ``mcbat.solving.GAME_INPUT_FIELDS`` (SI:
        m/s, rad, rad/s, m, kg).
    settings : SolverSettings
        The impact solver's accuracy.
    into : GameSolution, optional
        Outputs of ``n`` rows to write to (``allocate_games``); fresh ones by default.

    Returns
    -------
    GameSolution
        The bat-frame inputs and outputs, the batted ball (field frame, SI) and the status.
    """
    result = allocate_games(inputs.shape[1]) if into is None else into
    await_group("game")
    game_kernel.solve_game_batch(inputs, settings.steps, settings.tolerance,
                                 settings.max_steps, result.frame, result.out,
                                 result.game_out, result.status, result.end_state)
    return result


def batted_ball_vectors(game: GameSolution) -> tuple[Floats, Floats]:
    """The batted balls' launch velocity (m/s) and spin (rad/s) of solved game
    situations: two new ``float64[3, n]`` arrays (field frame)."""
    out = game.game_out
    velocity: Floats = np.stack([out[i] for i in _V])
    spin: Floats = np.stack([out[i] for i in _W])
    return velocity, spin


def _starts(start: tuple[float, float, float] | Floats, n: int) -> Floats:
    starts: Floats = np.repeat(np.asarray(start, np.float64)[:, None], n, axis=1)
    return starts


def fly_balls(params: FlightParams, start: tuple[float, float, float] | Floats,
              velocity: Floats, spin: Floats) -> FlightSolution:
    """Fly balls in one air in parallel (``mcbat.core.flight.fly_batch``).

    Parameters
    ----------
    params : FlightParams
        The air, the ball and the integrator (SI; ``mcbat.study.flight.FlightSettings.params``).
    start : sequence of 3 float
        The launch point (m, field frame), the same for every ball.
    velocity, spin : ndarray of float64, shape (3, n)
        Launch velocity (m/s) and spin (rad/s), field frame, C-contiguous.

    Returns
    -------
    FlightSolution
        ``FLIGHT_FIELDS`` (SI) and the flight's status per ball.
    """
    n = velocity.shape[1]
    starts = _starts(start, n)
    result = allocate_flights(n)
    await_group("flight")
    flight_kernel.fly_batch(flight_kernel.pack_params(params), starts, velocity, spin,
                            result.out, result.status)
    return result


def fly_balls_each(params: Floats, start: Floats, velocity: Floats,
                   spin: Floats) -> FlightSolution:
    """Fly balls in parallel, each in its own air (``mcbat.core.flight.fly_batch_each``).

    Parameters
    ----------
    params : ndarray of float64, shape (14, n)
        Column ``i`` the packed parameters of ball ``i`` (``pack_params``: its air
        density's drag factor (1/m), wind (m/s), drag and lift scales, landing height (m)).
    start, velocity, spin : ndarray of float64, shape (3, n)
        Launch point (m), velocity (m/s) and spin (rad/s), field frame, C-contiguous.

    Returns
    -------
    FlightSolution
        ``FLIGHT_FIELDS`` (SI) and the flight's status per ball.
    """
    result = allocate_flights(velocity.shape[1])
    await_group("flight")
    flight_kernel.fly_batch_each(params, start, velocity, spin, result.out, result.status)
    return result


def heights_at_distance(params: Floats, start: Floats, velocity: Floats, spin: Floats,
                        distance: Floats) -> Floats:
    """Where each ball's horizontal distance from home plate first reaches ``distance``
    (m, per ball; ``mcbat.core.flight.height_at_distance_batch``).

    Arguments as ``fly_balls_each``. Returns ``float64[2, n]``: the height (m) and the
    spray angle (rad) there; NaN where the ball comes down before.
    """
    out: Floats = np.full((2, velocity.shape[1]), np.nan)
    # (a writable copy of a read-only distance: one compiled kernel, not one per flag)
    distance = np.require(distance, np.float64, ["C", "W"])
    await_group("flight")
    flight_kernel.height_at_distance_batch(params, start, velocity, spin, distance, out)
    return out


def solve_and_fly(inputs: Floats, settings: SolverSettings, params: FlightParams,
                  start: tuple[float, float, float] | Floats) -> GameFlight:
    """Solve game situations and fly their batted balls, as a game study's chunk does.

    Parameters
    ----------
    inputs : ndarray of float64, shape (len(GAME_INPUT_FIELDS), n)
        As ``solve_games``.
    settings : SolverSettings
        The impact solver's accuracy.
    params : FlightParams
        The flight's air, ball and integrator (SI).
    start : sequence of 3 float
        The launch point (m, field frame).

    Returns
    -------
    GameFlight
        The game's solution, the launch velocity (m/s) and spin (rad/s) and the flight.
        A row that the game could not solve flies NaN (its flight status says so).
    """
    game = solve_games(inputs, settings)
    velocity, spin = batted_ball_vectors(game)
    return GameFlight(game, velocity, spin, fly_balls(params, start, velocity, spin))


def batch_kernels(game: bool, flight: bool) -> list[Any]:
    """The jitted batch kernels (numba dispatchers) a run calls, for asking whether their
    machine code is cached (``mcbat.core.jit.is_cold``): the bat frame's, or the game's
    (and the flight's, with ``flight``)."""
    if not game:
        return [impact_kernel.solve_batch]
    games = game_kernel.solve_game_batch
    return [games, flight_kernel.fly_batch] if flight else [games]
