"""Solve a study's own samples at given parameters: the true measured inputs and
observables of a simulated table (``mcbat.stats.measurements.synthesize``), and the
batted balls of a game kernel's input rows (population templates)."""

from __future__ import annotations

import numpy as np

from mcbat.core.status import ImpactStatus
from mcbat.solving import (
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    INPUT_FIELDS,
    OUTPUT_FIELDS,
    solve_games,
    solve_impacts,
)
from mcbat.solving.derived import derive, derive_game
from mcbat.stats.columns import GAME_WRITTEN
from mcbat.stats.models.draws import GameModel

__all__ = ["solve_game_inputs", "solve_study"]

def solve_study(study, rows, seed, params):
    """Solve the study's first ``rows`` samples (seed ``seed``) with ``params`` (``{"e": ...,
    "mu": ..., "e_x": ...}``, None: the study's) overriding its values.

    Returns
    -------
    measured, observed : dict of str -> ndarray
        The measured inputs a table of this kind carries and its observables, in the
        table's units (``mcbat.stats.columns``).
    ok : ndarray of bool
        Rows whose impact was solved.
    """
    if getattr(study, "kind", None) == "game":
        return _solve_game(study, rows, seed, params)
    return _solve_drop_test(study, rows, seed, params)


def _solve_drop_test(study, rows, seed, params):
    """A drop test's true inputs (table units), observables and good rows."""
    cols = study.sample(0, rows, seed)
    for name, value in params.items():
        if value is not None:
            cols[name] = np.full(rows, float(value))
    inputs = np.stack([np.asarray(cols[name], np.float64) for name in INPUT_FIELDS])
    out, status, _ = solve_impacts(inputs, study.solver_settings)
    o = {name: out[i] for i, name in enumerate(OUTPUT_FIELDS)}
    derived = derive([o[f"ball_v{c}"] for c in "xyz"], [o[f"ball_w{c}"] for c in "xyz"])
    measured = {"impact_parameter": cols["impact_parameter"], "spin_in": cols["ball_wz_in"]}
    observed = {"exit_speed": derived["exit_speed"],
                "scattering_angle": derived["scattering_angle"],
                "spin_out": derived["spin_axial"]}
    return measured, observed, status == ImpactStatus.OK


def _solve_game(study, rows, seed, params):
    """A game's true measured inputs (table units), batted balls and good rows."""
    inputs = study.sample_inputs(0, rows, seed)
    cols = {name: inputs[i] for i, name in enumerate(GAME_INPUT_FIELDS)}
    for name, value in params.items():
        if value is not None:
            inputs[GameModel.PARAMETERS[name]] = value
    batted, ok = solve_game_inputs(study, inputs)
    measured = {name: cols[name].copy() / GameModel.MEASURED[name][1] for name in GAME_WRITTEN}
    observed = {name: batted[name] for name in ("launch_speed", "launch_angle", "spray_angle",
                                                "spin_rate")}
    return measured, observed, ok


def solve_game_inputs(study, inputs):
    """Solve a game kernel's input rows (``mcbat.solving.GAME_INPUT_FIELDS`` x n)
    with the study's solver settings: the batted balls' Statcast outputs
    (``mcbat.solving.derived.derive_game``) and which rows were solved."""
    _, _, game_out, status, _ = solve_games(inputs, study.solver_settings)
    g = {name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)}
    batted = derive_game([g[f"field_ball_v{c}"] for c in "xyz"],
                         [g[f"field_ball_w{c}"] for c in "xyz"])
    return batted, status == ImpactStatus.OK
