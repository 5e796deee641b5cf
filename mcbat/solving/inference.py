"""The contact inference's batch kernel (``mcbat.core.contact_inference``): its call,
its settings, modes and status codes. Apart from the rest of ``mcbat.solving`` so that
whoever does not infer does not load it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from mcbat.core.contact_inference import solver
from mcbat.core.geometry import ProfileTable
from mcbat.core.jit import FunctionAddress, await_group
from mcbat.core.swing.game import GAME_ROW_SIGNATURE, solve_game_row

__all__ = ["INFERENCE_STATUS_NAMES", "INFER_BAT_SPEED", "INFER_FROM_BARREL_END",
           "INFER_NEAREST_BAT_SPEED", "OBSERVED_FIELDS", "SOLUTION_FIELDS",
           "InferenceSettings", "InferenceSolution", "InferenceStatus", "infer_contacts"]

Floats = NDArray[np.float64]
Codes = NDArray[np.int8]

# What is inferred per ball (a mode), the rows of the solution and of the observed launch
# (m/s, rad), the status codes and their names, and the settings of the Newton iteration
# and of the impact solver inside it.
INFER_BAT_SPEED = solver.INFER_BAT_SPEED
INFER_FROM_BARREL_END = solver.INFER_FROM_BARREL_END
INFER_NEAREST_BAT_SPEED = solver.INFER_NEAREST_BAT_SPEED
SOLUTION_FIELDS = solver.SOLUTION_FIELDS
OBSERVED_FIELDS = solver.OBSERVED_FIELDS
InferenceStatus = solver.InferenceStatus
INFERENCE_STATUS_NAMES = solver.INFERENCE_STATUS_NAMES
InferenceSettings = solver.InferenceSettings


class InferenceSolution(NamedTuple):
    """Contacts inferred from measured batted balls (``n`` rows)."""

    #: ``float64[len(SOLUTION_FIELDS), n]`` (SI).
    solution: Floats
    #: ``float64[3, n]``: launch speed (relative) and angles (rad) missed.
    residual: Floats
    #: ``int8[n]``: a code of ``InferenceStatus``.
    status: Codes
    #: ``int32[n]``: Newton iterations.
    iterations: NDArray[np.int32]
    #: ``int32[n]``: game kernel evaluations.
    evaluations: NDArray[np.int32]


#: The game kernel's row function, which the inference kernel calls by address: compiled
#: (or loaded) once, with the game kernel's group, not inside the inference kernel.
_GAME_ROW = FunctionAddress(solve_game_row, GAME_ROW_SIGNATURE, group="game")


def infer_contacts(game_inputs: Floats, observed: Floats, mode: NDArray[np.int8],
                   table: ProfileTable, loc_z: Floats, loc_f: Floats,
                   settings: InferenceSettings) -> InferenceSolution:
    """Infer the contacts behind measured batted balls in parallel
    (``mcbat.core.contact_inference.infer_contact_batch``).

    Parameters
    ----------
    game_inputs : ndarray of float64, shape (len(GAME_INPUT_FIELDS), n)
        The game situations (SI), the unknowns' rows holding their starting values.
    observed : ndarray of float64, shape (3, n)
        Launch speed (m/s), launch and spray angle (rad).
    mode : ndarray of int8, shape (n,)
        What is inferred per ball (``INFER_BAT_SPEED``, ``INFER_FROM_BARREL_END``,
        ``INFER_NEAREST_BAT_SPEED``).
    table : ProfileTable
        The bat's profile (``mcbat.core.geometry.profile_table``).
    loc_z, loc_f : ndarray of float64
        The restitution's location factor: positions (m) and factors.
    settings : InferenceSettings
        The Newton iteration's and the impact solver's settings.

    Returns
    -------
    InferenceSolution
        With no ball the kernel is not called (its outputs are empty).
    """
    result = InferenceSolution(*solver.allocate_inference_outputs(game_inputs.shape[1]))
    if game_inputs.shape[1]:
        await_group("inference")
        solver.infer_contact_batch(game_inputs, observed, mode, table, loc_z, loc_f, settings,
                                   _GAME_ROW, *result)
    return result
