"""The rows of a Statcast table the flight comparison and the flight fit leave out, counted
by reason (``mcbat fit --flight``, ``mcbat reproduce statcast``).

``mcbat.papers.statcast.compare.select_balls`` keeps the fly balls, line drives and
home runs with every measurement the flight needs; ``flight_left_out`` says why each
other row of the table was left out, in the order the checks are made (a row is counted
under the first reason that applies), and, given the balls a fit used, why the kept balls
were not fitted. The counts add up: ``rows - used == sum(counts)``, the reader's own
(``duplicate pitches``, already gone from the table) aside.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from mcbat.papers.statcast.compare import BATTED_TYPES, eligible_window

__all__ = ["flight_left_out", "selection_left_out"]

_MEASURED = ("launch_speed", "launch_angle", "spray_angle", "hit_distance_sc")


def selection_left_out(table: pd.DataFrame) -> dict:
    """The rows of ``table`` (the tidy table of ``mcbat.statcast.read``) that
    ``mcbat.papers.statcast.compare.select_balls`` leaves out, by reason, with the
    reader's own (``table.attrs["statcast"]["left_out"]``) first. Reasons counted 0 are
    kept (the keys are always the same)."""
    events = table["events"].astype("string")
    home_run = (events == "home_run").fillna(False).to_numpy(bool)
    batted = table["bb_type"].astype("string").isin(BATTED_TYPES).fillna(False) \
        .to_numpy(bool) | home_run
    numbers = {c: pd.to_numeric(table[c], errors="coerce").to_numpy(float)
               for c in (*_MEASURED, "elevation")}
    with np.errstate(invalid="ignore"):
        measured = np.logical_and.reduce([np.isfinite(numbers[c]) for c in _MEASURED]) & \
            (numbers["hit_distance_sc"] > 0) & (numbers["launch_speed"] > 0)
    elevation = np.isfinite(numbers["elevation"])
    side = table["handedness"].astype("string").isin(("R", "L")).fillna(False).to_numpy(bool)
    out = dict(table.attrs.get("statcast", {}).get("left_out", {}))
    out["not a fly ball, line drive or home run"] = int((~batted).sum())
    out["without launch speed, angle, spray angle or distance"] = int(
        (batted & ~measured).sum())
    out["without a park elevation"] = int((batted & measured & ~elevation).sum())
    out["without the batter's side"] = int((batted & measured & elevation & ~side).sum())
    return out


def flight_left_out(table: pd.DataFrame, balls: pd.DataFrame, used: int,
                    fit_classes=("catch", "home_run")) -> dict:
    """The rows of ``table`` a flight fit of ``balls`` (``select_balls(table)``) did not
    use, by reason: ``selection_left_out``, then the line drives and the fly balls
    launched outside the window
    (``mcbat.papers.statcast.compare.WINDOW_DEG``), the balls of a class not fitted
    (hits, infield catches), and those with no prediction (no spin, or a ball that never
    rises to its catch height): ``used`` is the number of balls fitted."""
    out = selection_left_out(table)
    window = eligible_window(balls)
    fitted_class = balls["comparison"].isin(fit_classes).to_numpy(bool)
    out["line drives, and fly balls launched outside 20-50 deg"] = int(
        (~window & fitted_class).sum())
    out["hits and infield catches (not fitted)"] = int((~fitted_class).sum())
    out["no predicted landing (no spin, or never rising to the catch height)"] = int(
        (window & fitted_class).sum()) - int(used)
    return out
