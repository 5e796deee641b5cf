"""Which rows of a Statcast table are balls in play (shared by the reader and the
collision columns, so neither imports the other)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["balls_in_play"]


def balls_in_play(df: pd.DataFrame) -> NDArray[np.bool_]:
    """Boolean mask of the balls put in play (``description`` starting with
    ``hit_into_play``: Savant's ``hit_into_play``, and ``hit_into_play_no_out`` /
    ``hit_into_play_score`` of exports before 2019's change)."""
    return df["description"].astype(str).str.startswith("hit_into_play").to_numpy()
