"""The game situation: field frame <-> bat frame, and the game kernel around
``mcbat.core.cabo2012.solve_impact`` (equations and sources in ``README.md``)."""

from mcbat.core.swing.frames import (
    SWEET_SPOT_FROM_BARREL_END,
    BatBody,
    GameContact,
    Pitch,
    Swing,
    bat_frame,
    pitch_state,
    swing_state,
)
from mcbat.core.swing.game import (
    FRAME_FIELDS,
    GAME_INPUT,
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    allocate_game_outputs,
    bat_frame_columns,
    incoming_state,
    solve_game_batch,
)

__all__ = ["FRAME_FIELDS", "GAME_INPUT", "GAME_INPUT_FIELDS", "GAME_OUTPUT_FIELDS",
           "SWEET_SPOT_FROM_BARREL_END", "BatBody", "GameContact", "Pitch", "Swing",
           "allocate_game_outputs", "bat_frame", "bat_frame_columns", "incoming_state",
           "pitch_state", "solve_game_batch", "swing_state"]
