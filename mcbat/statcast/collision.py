"""The collision measured per ball: Statcast's bat speed, pitch speed and launch speed
combined (``docs/statcast.md``, "The collision measured").

For a tracked ball in play (put in play, with ``bat_speed``, ``launch_speed`` and the
plate ``pitch_speed`` measured):

- ``collision_efficiency`` ``q = (launch_speed - bat_speed) / (pitch_speed + bat_speed)``,
  the ratio that makes ``launch_speed = q pitch_speed + (1 + q) bat_speed`` (Nathan's
  collision efficiency), with the pitch speed at the front of the plate;
- ``squared_up_fraction`` ``launch_speed / (1.23 bat_speed + 0.23 pitch_speed)``:
  Statcast's "squared-up rate" of one swing, the exit velocity as a share of the largest
  Statcast deems possible for that bat speed and pitch speed (the same formula with
  ``q = 0.23``);
- ``squared_up``: ``squared_up_fraction >= 0.8`` (Statcast's squared-up swing).

Elsewhere NaN (``squared_up``: pandas' missing value ``<NA>`` in a ``"boolean"``
column). ``collision_summary`` sums them up for comparison with a model.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    import pandas as pd

_Floats = NDArray[np.float64]

__all__ = ["COLLISION_UNITS", "SQUARED_UP_BAT", "SQUARED_UP_PITCH", "SQUARED_UP_THRESHOLD",
           "collision_columns", "collision_summary", "is_bunt", "squared_up_maximum"]

COLLISION_UNITS = {"collision_efficiency": "1", "squared_up_fraction": "1",
                   "squared_up": "bool"}
"""The columns ``collision_columns`` adds to the tidy table, with their units."""

SQUARED_UP_BAT = 1.23
"""Statcast's largest possible exit velocity per mph of bat speed (``1 + q``, q = 0.23)."""
SQUARED_UP_PITCH = 0.23
"""... and per mph of pitch speed at the plate (``q``)."""
SQUARED_UP_THRESHOLD = 0.8
"""A swing is squared up when its exit velocity is at least this share of the largest."""

_BUNT_WORD = re.compile(r"\bbunt", re.IGNORECASE)


def squared_up_maximum(bat_speed: ArrayLike, pitch_speed: ArrayLike) -> _Floats:
    """Statcast's largest possible exit velocity (mph) for a bat speed and a pitch speed
    at the plate (mph): ``1.23 bat_speed + 0.23 pitch_speed``."""
    return (SQUARED_UP_BAT * np.asarray(bat_speed, dtype=float)
            + SQUARED_UP_PITCH * np.asarray(pitch_speed, dtype=float))


def _tracked(df: pd.DataFrame, in_play: NDArray[np.bool_]
             ) -> tuple[NDArray[np.bool_], _Floats, _Floats, _Floats]:
    speed = df["bat_speed"].to_numpy(dtype=float)
    launch = df["launch_speed"].to_numpy(dtype=float)
    pitch = df["pitch_speed"].to_numpy(dtype=float)
    ok = (in_play & np.isfinite(speed) & np.isfinite(launch) & np.isfinite(pitch)
          & (speed > 0.0) & (pitch + speed > 0.0))
    return ok, speed, launch, pitch


def collision_columns(df: pd.DataFrame, in_play: ArrayLike) -> dict[str, Any]:
    """``collision_efficiency``, ``squared_up_fraction`` (float64, NaN where not a tracked
    ball in play) and ``squared_up`` (pandas ``"boolean"``, ``<NA>`` there) of the tidy
    table ``df``; ``in_play`` is the balls-in-play mask. Returns a dict of columns."""
    import pandas as pd

    ok, speed, launch, pitch = _tracked(df, np.asarray(in_play, dtype=bool))
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(ok, (launch - speed) / (pitch + speed), np.nan)
        fraction = np.where(ok, launch / squared_up_maximum(speed, pitch), np.nan)
    squared = pd.array(np.where(ok, fraction >= SQUARED_UP_THRESHOLD, False),
                       dtype="boolean")
    squared[~ok] = pd.NA
    return {"collision_efficiency": q, "squared_up_fraction": fraction,
            "squared_up": squared}


def is_bunt(description: Collection[object] | None = None,
            events: Collection[object] | None = None,
            des: Collection[object] | None = None) -> NDArray[np.bool_]:
    """Which rows Savant marks as bunts, from any of its text columns (arrays of str or
    missing): ``description`` containing ``bunt`` (``foul_bunt``, ``missed_bunt``,
    ``bunt_foul_tip``), ``events`` starting ``sac_bunt``, or the play's words ``des``
    with the word "bunt" ("... bunt grounds out ...", "... on a sacrifice bunt ...").
    Savant's ``bb_type`` has no bunt class in the pitch-level export."""
    columns = [c for c in (description, events, des) if c is not None]
    if not columns:
        raise ValueError("is_bunt needs at least one column")
    n = len(columns[0])
    out = np.zeros(n, dtype=bool)

    def text(values: Iterable[object]) -> list[str]:
        return [v.lower() if isinstance(v, str) else "" for v in values]

    if description is not None:
        out |= np.array(["bunt" in t for t in text(description)], dtype=np.bool_)
    if events is not None:
        out |= np.array([t.startswith("sac_bunt") for t in text(events)], dtype=np.bool_)
    if des is not None:
        out |= np.array([_BUNT_WORD.search(t) is not None for t in text(des)],
                        dtype=np.bool_)
    return out


def collision_summary(table: pd.DataFrame, *, bat_speed_floor: float = 40.0,
                      exclude_bunts: bool = True,
                      bat_speed_bins: Sequence[float] = (40, 55, 60, 65, 70, 75, 80, 90),
                      attack_angle_bins: Sequence[float] = (-30, -10, 0, 5, 10, 15, 20, 30,
                                                            60)) -> dict[str, Any]:
    """The measured collision of a tidy table's tracked balls in play, for comparison
    with a model.

    Parameters
    ----------
    table : pandas.DataFrame
        A tidy table (``mcbat.statcast.read``).
    bat_speed_floor : float
        mph; swings slower than this (bunts, check swings) are left out.
    exclude_bunts : bool
        Leave out the rows Savant marks as bunts (``is_bunt``).
    bat_speed_bins, attack_angle_bins : sequence of float
        Bin edges (mph, deg) of the binned means.

    Returns
    -------
    dict
        JSON-ready: ``balls`` (tracked balls in play used), ``left_out`` (bunts, below the
        floor); ``collision_efficiency`` quantiles (``p01``, ``p10``, ``p25``, ``median``,
        ``p75``, ``p90``, ``p99``, ``max``, ``mean``); ``upper_edge`` (``p99``, ``max``,
        and ``max_squared_up``: the largest q of a squared-up ball, and Statcast's own
        ceiling ``q = 0.23``); ``squared_up_rate`` (share of the balls);
        ``launch_speed_vs_bat_speed`` (least-squares ``slope`` mph/mph, ``intercept``
        mph, correlation ``r``); ``by_bat_speed`` and ``by_attack_angle`` (per bin:
        ``low``, ``high``, ``balls``, mean ``collision_efficiency``, its ``p90``, mean
        ``squared_up_fraction``, mean ``launch_speed``).
    """
    from mcbat.statcast.plays import balls_in_play

    columns = collision_columns(table, balls_in_play(table))
    q = columns["collision_efficiency"]
    fraction = columns["squared_up_fraction"]
    speed = table["bat_speed"].to_numpy(dtype=float)
    used = np.isfinite(q)
    bunts = is_bunt(table["description"].to_numpy(object), table["events"].to_numpy(object),
                    table["des"].to_numpy(object)) & used
    slow = used & ~(speed >= bat_speed_floor) & ~bunts
    if exclude_bunts:
        used &= ~bunts
    used &= ~slow
    out: dict[str, Any] = {"balls": int(used.sum()),
                           "left_out": {"bunts": int(bunts.sum()) if exclude_bunts else 0,
                                        "below_floor": int(slow.sum())}}
    if not used.any():
        return out
    qs = q[used]
    levels = {"p01": 0.01, "p10": 0.1, "p25": 0.25, "median": 0.5, "p75": 0.75,
              "p90": 0.9, "p99": 0.99}
    out["collision_efficiency"] = {k: float(np.quantile(qs, v)) for k, v in levels.items()}
    out["collision_efficiency"].update(max=float(qs.max()), mean=float(qs.mean()))
    squared = fraction[used] >= SQUARED_UP_THRESHOLD
    out["upper_edge"] = {"p99": float(np.quantile(qs, 0.99)), "max": float(qs.max()),
                         "max_squared_up": float(qs[squared].max()) if squared.any()
                         else None,
                         "statcast_ceiling": SQUARED_UP_PITCH}
    out["squared_up_rate"] = float(squared.mean())
    launch = table["launch_speed"].to_numpy(dtype=float)[used]
    bats = speed[used]
    if len(bats) > 2 and np.ptp(bats) > 0:
        slope, intercept = np.polyfit(bats, launch, 1)
        out["launch_speed_vs_bat_speed"] = {
            "slope": float(slope), "intercept": float(intercept),
            "r": float(np.corrcoef(bats, launch)[0, 1])}
    attack = table["attack_angle"].to_numpy(dtype=float)[used]
    out["by_bat_speed"] = _binned(bats, bat_speed_bins, qs, fraction[used], launch)
    out["by_attack_angle"] = _binned(attack, attack_angle_bins, qs, fraction[used], launch)
    return out


def _binned(x: _Floats, edges: Sequence[float], q: _Floats, fraction: _Floats,
            launch: _Floats) -> list[dict[str, float | int]]:
    rows: list[dict[str, float | int]] = []
    for low, high in zip(edges[:-1], edges[1:]):
        inside = (x >= low) & (x < high)
        if not inside.any():
            continue
        rows.append({"low": float(low), "high": float(high), "balls": int(inside.sum()),
                     "collision_efficiency": float(q[inside].mean()),
                     "collision_efficiency_p90": float(np.quantile(q[inside], 0.9)),
                     "squared_up_fraction": float(fraction[inside].mean()),
                     "launch_speed": float(launch[inside].mean())})
    return rows
