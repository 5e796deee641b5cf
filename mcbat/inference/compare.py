"""The inferred backspin against Nathan's average spin model of tracked batted balls.

Nathan's model (``mcbat.statcast.spin``) rises 120 rpm per degree of launch angle with
the spray angle held (``-763 + 120 LA + 21 phi``, the batter's frame). A slope of the
backspin on the launch angle alone also carries what the spray angle does as the launch
angle rises, so the like-for-like comparisons are (``docs/spin_inference.md``, "Like
for like"): the inferred slope against the model's slope *on the same balls*, and the
launch angle's coefficient with the spray angle held against 120.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from mcbat.statcast.spin import HANDEDNESS, nathan_average_spin

__all__ = ["LAUNCH_ANGLES", "NATHAN_SLOPE", "BackspinSlopes", "backspin_slopes"]

#: The launch angles (deg) over which the slopes are taken: where Nathan's linear model
#: was fitted to ordinary batted balls.
LAUNCH_ANGLES = (10.0, 40.0)
#: The launch angle's coefficient of Nathan's model (rpm per deg).
NATHAN_SLOPE = 120.0
#: The fewest balls a slope is given for.
MIN_BALLS = 20


@dataclass(frozen=True)
class BackspinSlopes:
    """Slopes of backspin on launch angle (rpm per deg) over ``LAUNCH_ANGLES``."""

    #: Converged balls in the range.
    balls: int
    #: The inferred backspin on the launch angle alone.
    inferred: float
    #: Nathan's model, evaluated on the same balls, on the launch angle alone.
    nathan_same_balls: float
    #: The inferred backspin's launch-angle coefficient with the batter-frame spray angle
    #: held (as Nathan's 120 is).
    inferred_spray_held: float


def backspin_slopes(balls: pd.DataFrame, spin: pd.DataFrame) -> BackspinSlopes | None:
    """The slopes of ``infer_spin``'s converged balls (``spin``, rows as ``balls``: the
    tidy table's ``launch_angle``, ``spray_angle`` (deg) and ``handedness``); None with
    fewer than ``MIN_BALLS`` balls in the range."""
    la = balls["launch_angle"].to_numpy(float)
    spray = balls["spray_angle"].to_numpy(float)
    hand = balls["handedness"].to_numpy(dtype=object)
    backspin = spin["backspin"].to_numpy(float)
    low, high = LAUNCH_ANGLES
    rows = ((spin["inference_status"].to_numpy() == "converged") & (la >= low) & (la <= high)
            & np.isfinite(backspin) & np.isfinite(spray) & np.isin(hand, list(HANDEDNESS)))
    if rows.sum() < MIN_BALLS:
        return None
    la, spray, hand, backspin = la[rows], spray[rows], hand[rows], backspin[rows]
    nathan, _ = nathan_average_spin(la, spray, hand)
    mirror = np.array([HANDEDNESS[h] for h in hand])
    design = np.column_stack([np.ones(la.size), la, mirror * spray])
    held = np.linalg.lstsq(design, backspin, rcond=None)[0][1]
    return BackspinSlopes(int(rows.sum()), float(np.polyfit(la, backspin, 1)[0]),
                          float(np.polyfit(la, nathan, 1)[0]), float(held))
