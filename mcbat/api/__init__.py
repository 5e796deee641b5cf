"""Python API for single cases: build an impact, a game situation or a flight, solve it,
read the result (or its JSON answer, with units).

One job per module:

``mcbat.api.contract``  the JSON of ``mcbat impact`` and ``mcbat flight``: the
                           answers (a result -> JSON with a ``units`` block), the units,
                           the readers of shared parts (numbers with units, balls, bats)
``mcbat.api.impact``    one impact in the bat frame (SI): ``ImpactCase``,
                           ``solve`` -> ``ImpactResult``; ``SolverSettings``
``mcbat.api.game``      one pitch and swing in the field frame (SI in; the batted ball
                           in mph, deg, rpm out): ``GameCase``, ``solve_game``
                           -> ``GameResult``
``mcbat.api.flight``    one batted ball's flight (SI in; ft and m out):
                           ``FlightCase`` (``FlightCase.from_result`` for a game's
                           ball), ``solve_flight`` -> ``FlightResult``
``mcbat.api.pitch``     a pitch's speed at the plate from its release speed (the
                           JSON's ``pitch.release_speed``): ``mcbat.api.pitch.plate_speed``

Each case type reads its own JSON (``impact_case_from_dict``, ``game_case_from_dict``,
``flight_case_from_dict``; a game's or flight's bare numbers in the field's units, mph,
deg, rpm, ft: ``mcbat.api.contract.FIELD_KEYS``); ``case_from_dict`` and
``any_case_from_dict`` pick one.
``mcbat.solve`` takes any of the three cases, a JSON object or a JSON file.

Example
-------
A batted ball read as ``mcbat flight`` reads it (bare numbers in mph, deg and rpm), then
flown (an impact built field by field: ``mcbat.api.impact``; a game: ``mcbat.api.game``):

>>> from mcbat.api import any_case_from_dict, solve_flight
>>> ball = any_case_from_dict({"launch_speed": 103, "launch_angle": 27, "backspin": 2000})
>>> type(ball).__name__, 330 < solve_flight(ball).hit_distance < 480
('FlightCase', True)
"""

from typing import Any

from mcbat.api.flight import (
    MAX_TRAJECTORY_POINTS,
    FlightCase,
    FlightResult,
    flight_case_from_dict,
    solve_flight,
)
from mcbat.api.game import GAME_JSON_KEYS, GameCase, GameResult, game_case_from_dict, solve_game
from mcbat.api.impact import (
    MAX_AZIMUTH,
    Contact,
    ImpactCase,
    ImpactResult,
    SolverSettings,
    Vector,
    contact_problem,
    history,
    impact_case_from_dict,
    solve,
)
from mcbat.bodies import Ball, Bat
from mcbat.bodies.restitution import Restitution
from mcbat.errors import InputError
from mcbat.study.game_keys import is_game

__all__ = ["MAX_AZIMUTH", "MAX_TRAJECTORY_POINTS", "Ball", "Bat", "Contact", "FlightCase",
           "FlightResult", "GameCase", "GameResult", "ImpactCase", "ImpactResult",
           "Restitution", "SolverSettings", "Vector", "any_case_from_dict", "case_from_dict",
           "contact_problem",
           "flight_case_from_dict", "history", "solve", "solve_any", "solve_flight",
           "solve_game"]


# Defined here rather than in a submodule: it finds ``solve`` and ``solve_game`` by their
# names in this package, so that whoever replaces ``mcbat.api.solve`` (a test standing in
# a broken solver) reaches every caller of solve_any, the command line among them.
def solve_any(case: ImpactCase | GameCase,
              settings: SolverSettings = SolverSettings(),  # noqa: B008 (frozen)
              *, json_keys: bool = False) -> ImpactResult | GameResult:
    """``solve`` for an ``ImpactCase``, ``solve_game`` for a ``GameCase``
    (with ``json_keys``, a game's errors name the JSON keys, ``pitch.speed``)."""
    if isinstance(case, GameCase):
        try:
            return solve_game(case, settings)
        except InputError as err:
            if json_keys and err.field in GAME_JSON_KEYS:
                raise InputError(".".join(GAME_JSON_KEYS[err.field]), err.message) from None
            raise
    return solve(case, settings)


def case_from_dict(data: Any) -> ImpactCase | GameCase:
    """A ``GameCase`` for a JSON case of ``mcbat impact`` with ``pitch``/``swing`` keys,
    else an ``ImpactCase``."""
    return game_case_from_dict(data) if is_game(data) else impact_case_from_dict(data)


def any_case_from_dict(data: Any) -> ImpactCase | GameCase | FlightCase:
    """The case of any JSON object ``mcbat impact`` or ``mcbat flight`` reads: a
    ``FlightCase`` for one with ``launch_speed`` (a game's answer among them), else
    ``case_from_dict``."""
    if isinstance(data, dict) and not is_game(data) and ("launch_speed" in data
                                                         or "bat_frame" in data):
        return flight_case_from_dict(data)
    return case_from_dict(data)
