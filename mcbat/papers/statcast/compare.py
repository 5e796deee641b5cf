"""Which measured balls are compared with the flight model, and how.

Statcast's ``hit_distance_sc`` is not always the carry to the ground. It is the horizontal
distance from home plate to the first thing the ball met: a fielder's glove, the ground or
a wall; for a home run, the trajectory projected to the ground (``docs/flight.md``). So each
ball is compared with the point of its predicted flight that the measurement refers to:

============== =============================================== ======================
``comparison`` which balls                                     predicted distance to
============== =============================================== ======================
``home_run``   ``events == "home_run"``                        the ground (z = 0)
``catch``      outs and errors (a fielder touched the ball      where the descending
               first) made by an outfielder                     ball passes the catch
                                                                height (6 ft)
``hit``        singles, doubles, triples                       the ground (its first
                                                                bounce; short of it
                                                                when the ball hit a
                                                                wall)
``infield``    outs and errors made by an infielder            not compared: the ball
               (``hit_location`` 1-6)                           was intercepted in
                                                                flight, often rising
============== =============================================== ======================

The catch height: a fly ball is caught between the waist and above the head, most often
around the chest or face of a standing fielder, ~5-7 ft above the ground; 6 ft is the middle
(the residual moves by ~0.5-1 ft per foot of catch height for a fly ball descending at
45-60 deg). Without a ``hit_location`` column every out counts as a catch.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from mcbat.errors import InputError

__all__ = ["BATTED_TYPES", "CATCH_HEIGHT_FT", "COMPARED", "REQUIRED", "WINDOW_DEG",
           "eligible_window", "select_balls"]

#: Batted-ball types compared (Statcast's ``bb_type``); home runs of any type too.
BATTED_TYPES = ("fly_ball", "line_drive")
#: Height (ft) at which a caught ball is compared.
CATCH_HEIGHT_FT = 6.0
#: Events after which the ball first met the ground or a wall, not a fielder.
HIT_EVENTS = frozenset({"single", "double", "triple"})
#: ``hit_location`` of the infielders (pitcher, catcher, 1B, 2B, 3B, SS).
INFIELD_POSITIONS = frozenset({1, 2, 3, 4, 5, 6})
#: Columns the comparison needs (the tidy table of ``mcbat.statcast.read``).
REQUIRED = ("launch_speed", "launch_angle", "spray_angle", "hit_distance_sc", "bb_type",
            "events", "handedness", "elevation")
#: The comparison classes that are flown and summarised.
COMPARED = ("catch", "home_run", "hit")


def select_balls(table: pd.DataFrame, source: str | None = None) -> pd.DataFrame:
    """The fly balls, line drives and home runs of ``table`` with a measured distance, with
    their ``comparison`` class and ``compare_height`` (ft) (module docstring).

    Balls with a missing launch speed, angle, spray angle, distance, elevation or batter's
    side are left out. Infield outs are kept, with ``comparison = "infield"``, and not flown.

    Raises
    ------
    InputError
        Naming a missing column, or ``hit_distance_sc`` when no ball qualifies.
    """
    for column in REQUIRED:
        if column not in table.columns:
            raise InputError(column, f"missing column (the comparison needs "
                             f"{', '.join(REQUIRED)})", source)
    events = table["events"].astype("string")
    kind = table["bb_type"].astype("string")
    home_run = (events == "home_run").fillna(False).to_numpy(bool)
    batted = kind.isin(BATTED_TYPES).fillna(False).to_numpy(bool) | home_run
    numbers = {c: pd.to_numeric(table[c], errors="coerce").to_numpy(float)
               for c in ("launch_speed", "launch_angle", "spray_angle", "hit_distance_sc",
                         "elevation")}
    finite = np.logical_and.reduce([np.isfinite(v) for v in numbers.values()])
    side = table["handedness"].astype("string").isin(("R", "L")).fillna(False).to_numpy(bool)
    keep = batted & finite & side & (numbers["hit_distance_sc"] > 0) & (
        numbers["launch_speed"] > 0)
    if not keep.any():
        raise InputError("hit_distance_sc", f"no fly balls, line drives or home runs with a "
                         f"measured distance, launch speed, launch angle and spray angle "
                         f"among {len(table)} rows", source)
    balls = table.loc[keep].reset_index(drop=True).copy()
    for c, v in numbers.items():
        balls[c] = v[keep]
    ev = balls["events"].astype("string").fillna("")
    comparison = np.where(ev == "home_run", "home_run",
                          np.where(ev.isin(HIT_EVENTS), "hit", "catch")).astype(object)
    if "hit_location" in balls.columns:
        location = pd.to_numeric(balls["hit_location"], errors="coerce")
        infield = location.isin(INFIELD_POSITIONS).to_numpy(bool)
        comparison[(comparison == "catch") & infield] = "infield"
    balls["comparison"] = pd.Categorical(comparison,
                                         categories=(*COMPARED, "infield"))
    balls["compare_height"] = np.where(np.isin(comparison, ("catch", "infield")),
                                       CATCH_HEIGHT_FT, 0.0)
    return balls


#: The launch angles (deg) of the fly balls and home runs every flight is judged on: where
#: the carry depends most on the air and the ball, and least on where a fielder stood.
WINDOW_DEG = (20.0, 50.0)


def eligible_window(balls: pd.DataFrame) -> np.ndarray:
    """Boolean mask of the fly balls and home runs launched at 20-50 deg
    (``WINDOW_DEG``) among ``balls`` (a ``select_balls`` frame), caught in the
    outfield or home runs: the balls every flight is judged on."""
    angle = balls["launch_angle"].to_numpy(float)
    kind = balls["bb_type"].astype("string").fillna("")
    comparison = balls["comparison"].astype("string").fillna("")
    return ((angle >= WINDOW_DEG[0]) & (angle <= WINDOW_DEG[1])
            & ((kind == "fly_ball") | (comparison == "home_run")).to_numpy(bool)
            & comparison.isin(COMPARED).to_numpy(bool))


def launch_angle_bins(launch_angle, width=10.0):
    """Left edge (deg) of each ball's ``width``-degree launch-angle bin."""
    return np.floor(np.asarray(launch_angle, float) / width) * width


def residual_stats(residual) -> dict:
    """Median, mean and rms (ft) of residuals, and their count (None when empty)."""
    r = np.asarray(residual, float)
    r = r[np.isfinite(r)]
    if r.size == 0:
        return {"n": 0, "median": None, "mean": None, "rms": None}
    return {"n": int(r.size), "median": float(np.median(r)), "mean": float(r.mean()),
            "rms": float(math.sqrt(np.mean(r * r)))}
