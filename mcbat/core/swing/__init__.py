"""The game situation: field frame <-> bat frame, and the game kernel around
:func:`mcbat.core.cabo2012.solve_impact` (equations and sources in ``README.md``)."""

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
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    allocate_game_outputs,
    solve_game_batch,
)

__all__ = ["GAME_INPUT_FIELDS", "GAME_OUTPUT_FIELDS", "SWEET_SPOT_FROM_BARREL_END", "BatBody",
           "GameContact", "Pitch", "Swing", "allocate_game_outputs", "bat_frame",
           "pitch_state", "solve_game_batch", "swing_state"]
