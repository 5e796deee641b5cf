"""Where a game was played: Statcast's ``home_team`` and season -> the park and its elevation.

The table is ``data/mlb_parks.csv`` (provenance in ``data/README.md``): one row per park a
team called home over a span of seasons, with Savant's team code, the park's name, its
elevation in ft and the source of that number. Seasons in which a team played its home
games in more than one park (Toronto 2021) or where no sourced elevation is at hand have
no elevation: the reader gives NaN and counts those rows, it never guesses.

A Savant export names the home team, not the venue, so games a team hosted away from its
park (neutral-site series abroad, special events) get the home park's elevation; the
export carries no venue column to tell them apart.
"""

from __future__ import annotations

import csv
import functools
import math
from importlib import resources

import numpy as np

__all__ = ["PARKS_FILE", "elevation", "parks"]

PARKS_FILE = "mlb_parks.csv"
"""The park table inside the resource package ``mcbat.data``."""


@functools.cache
def parks() -> tuple[dict, ...]:
    """The park table as dicts (``home_team``, ``park``, ``first_season``,
    ``last_season``, ``elevation_ft``, ``source``), cached."""
    text = resources.files("mcbat.data").joinpath(PARKS_FILE).read_text(encoding="utf-8")
    rows = []
    for row in csv.DictReader(line for line in text.splitlines()
                              if line.strip() and not line.startswith("#")):
        rows.append({
            "home_team": row["home_team"].strip(),
            "park": row["park"].strip(),
            "first_season": int(row["first_season"]),
            "last_season": int(row["last_season"]) if row["last_season"].strip() else 9999,
            "elevation_ft": (float(row["elevation_ft"]) if row["elevation_ft"].strip()
                             else math.nan),
            "source": row["source"].strip(),
        })
    return tuple(rows)


def elevation(home_team, game_year):
    """Elevation (ft) of the home park of each row; NaN where the team and season are not
    in the table or the table has no elevation for them.

    Parameters
    ----------
    home_team : array_like of str
        Savant's ``home_team`` codes.
    game_year : array_like of float
        Seasons (NaN allowed).

    Returns
    -------
    ndarray of float
    """
    teams = np.asarray(home_team, dtype=object)
    years = np.asarray(game_year, dtype=float)
    out = np.full(teams.shape, np.nan)
    for park in parks():
        rows = ((teams == park["home_team"]) & (years >= park["first_season"])
                & (years <= park["last_season"]))
        out[rows] = park["elevation_ft"]
    return out
