"""Where a game was played: Statcast's ``home_team`` and date -> the park, its elevation,
orientation, roof and outfield fence.

The tables are ``data/mlb_parks.csv`` and ``data/park_fences.csv`` (provenance in
``data/README.md``). A park row covers one ``home_team`` over a date span; short
neutral-site rows (``kind`` ``neutral``) win over the home park on their dates, then
``temporary`` rows, then ``home`` rows. A park's fences may have several configurations
over time (date spans in the fence table); ``fence`` picks the one standing on a
game's date when given the date.
"""

from __future__ import annotations

import csv
import functools
import math
from importlib import resources
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mcbat.errors import InputError

__all__ = ["FENCES_FILE", "PARKS_FILE", "elevation", "fence", "fence_config",
           "fence_configurations", "fences", "park_of", "park_value", "parks"]

PARKS_FILE = "mlb_parks.csv"
"""The park table inside the resource package ``mcbat.data``."""
FENCES_FILE = "park_fences.csv"
"""The fence table inside the resource package ``mcbat.data``."""

_PRIORITY = {"neutral": 0, "temporary": 1, "home": 2}
_NO_END = np.datetime64("9999-12-31")
_NO_START = np.datetime64("0001-01-01")


def _read(name: str) -> list[dict[str, str]]:
    text = resources.files("mcbat.data").joinpath(name).read_text(encoding="utf-8")
    return list(csv.DictReader(line for line in text.splitlines()
                               if line.strip() and not line.startswith("#")))


def _float(cell: str) -> float:
    return float(cell) if cell.strip() else math.nan


@functools.cache
def parks() -> tuple[dict[str, Any], ...]:
    """The park table as dicts, cached.

    Keys: ``park_id``, ``home_team``, ``park``, ``first_date`` and ``last_date``
    (``numpy.datetime64[D]``; an open span ends 9999-12-31), ``kind``, ``roof``,
    ``elevation_ft`` (ft), ``bearing_deg`` (deg from north, home plate to centre field;
    NaN where unsourced), ``latitude``, ``longitude`` (deg, NaN where unsourced), the
    ``*_source`` cells, and for older callers ``first_season``, ``last_season`` and
    ``source`` (the elevation's source).
    """
    rows: list[dict[str, Any]] = []
    for row in _read(PARKS_FILE):
        first = np.datetime64(row["first_date"].strip(), "D")
        last = (np.datetime64(row["last_date"].strip(), "D") if row["last_date"].strip()
                else _NO_END)
        rows.append({
            "park_id": row["park_id"].strip(), "home_team": row["home_team"].strip(),
            "park": row["park"].strip(), "first_date": first, "last_date": last,
            "kind": row["kind"].strip(), "roof": row["roof"].strip(),
            "elevation_ft": _float(row["elevation_ft"]),
            "elevation_source": row["elevation_source"].strip(),
            "bearing_deg": _float(row["bearing_deg"]),
            "bearing_source": row["bearing_source"].strip(),
            "latitude": _float(row["latitude"]), "longitude": _float(row["longitude"]),
            "coord_source": row["coord_source"].strip(),
            "first_season": int(str(first)[:4]),
            "last_season": 9999 if last == _NO_END else int(str(last)[:4]),
            "source": row["elevation_source"].strip(),
        })
    # neutral rows first so that they win
    rows.sort(key=lambda p: _PRIORITY[p["kind"]])
    return tuple(rows)


@functools.cache
def _park_info() -> dict[str, dict[str, Any]]:
    return {p["park_id"]: p for p in parks()}


def _dates(game_date: ArrayLike) -> NDArray[np.datetime64]:
    values = np.asarray(game_date)
    if values.dtype.kind == "M":
        return values.astype("datetime64[D]")
    out = np.full(values.shape, np.datetime64("NaT"), dtype="datetime64[D]")
    for i, v in np.ndenumerate(values):
        try:
            out[i] = np.datetime64(str(v)[:10], "D")
        except ValueError:
            pass  # a date that does not parse stays NaT: the row is matched to no park
    return out


def park_of(home_team: ArrayLike, game_date: ArrayLike) -> NDArray[np.object_]:
    """The park (``park_id``) of each row: the row of ``data/mlb_parks.csv`` whose team and
    date span hold the game; neutral-site rows win over temporary rows over home parks.

    Parameters
    ----------
    home_team : array_like of str
        Statcast ``home_team`` codes.
    game_date : array_like of datetime64 or str
        Game dates (``YYYY-MM-DD``); NaT or unparsable dates give no park.

    Returns
    -------
    ndarray of object
        ``park_id`` per row; None where the team or date is not in the table.
    """
    teams = np.asarray(home_team, dtype=object)
    dates = _dates(game_date)
    out = np.full(teams.shape, None, dtype=object)
    for park in reversed(parks()):  # lowest priority first, overwritten by higher
        rows = ((teams == park["home_team"]) & (dates >= park["first_date"])
                & (dates <= park["last_date"]))
        out[rows] = park["park_id"]
    return out


def park_value(park_ids: ArrayLike, key: str) -> NDArray[Any]:
    """One column of the park table (``elevation_ft``, ``roof``, ``bearing_deg``, ...) for
    each ``park_id`` (None gives NaN or None)."""
    info = _park_info()
    ids = np.asarray(park_ids, dtype=object)
    numeric = key in ("elevation_ft", "bearing_deg", "latitude", "longitude")
    out = np.full(ids.shape, np.nan if numeric else None, dtype=float if numeric else object)
    for i, pid in np.ndenumerate(ids):
        if pid in info:
            out[i] = info[pid][key]
    return out


def elevation(home_team: ArrayLike, game_year: ArrayLike | None = None,
              game_date: ArrayLike | None = None) -> NDArray[np.float64]:
    """Elevation (ft) of the park of each row; NaN where the team and date are not in the
    table.

    Parameters
    ----------
    home_team : array_like of str
        Statcast ``home_team`` codes.
    game_year : array_like of float, optional
        Seasons (NaN allowed); used when ``game_date`` is not given, with the park in use
        on 1 July of that season.
    game_date : array_like of datetime64 or str, optional
        Game dates; when given, each row's elevation is its date's park.

    Returns
    -------
    ndarray of float
    """
    if game_date is None:
        years = np.asarray(game_year, dtype=float)
        game_date = np.array([f"{int(y):04d}-07-01" if np.isfinite(y) else "NaT"
                              for y in years.ravel()]).reshape(years.shape)
    return park_value(park_of(home_team, game_date), "elevation_ft")


@functools.cache
def fence_configurations() -> tuple[dict[str, Any], ...]:
    """The fence configurations of ``data/park_fences.csv``, one dict per park and span.

    Keys: ``config_id`` (``park_id@first_date``, or ``park_id@opening`` for a
    configuration standing since the park opened), ``park_id``, ``first_date`` and
    ``last_date`` (``numpy.datetime64[D]``; open ends 0001-01-01 and 9999-12-31), and
    ``spray_angle_deg``, ``distance_ft``, ``height_ft`` (arrays sorted by spray angle, NaN
    where a cell is empty). Sorted by park and first date.
    """
    groups: dict[tuple[str, str, str], list[tuple[float, float, float]]] = {}
    for row in _read(FENCES_FILE):
        pid = row["park_id"].strip()
        first, last = row["first_date"].strip(), row["last_date"].strip()
        groups.setdefault((pid, first, last), []).append(
            (float(row["spray_angle_deg"]), _float(row["distance_ft"]),
             _float(row["height_ft"])))
    configs = []
    for (pid, first, last), points in groups.items():
        a, d, h = (np.array(c) for c in zip(*sorted(points)))
        configs.append({
            "config_id": f"{pid}@{first or 'opening'}", "park_id": pid,
            "first_date": np.datetime64(first, "D") if first else _NO_START,
            "last_date": np.datetime64(last, "D") if last else _NO_END,
            "spray_angle_deg": a, "distance_ft": d, "height_ft": h})
    configs.sort(key=lambda c: (c["park_id"], c["first_date"]))
    return tuple(configs)


@functools.cache
def fences() -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]]:
    """The fence table: ``{key: (spray_angle_deg, distance_ft, height_ft)}`` arrays sorted
    by spray angle (NaN where a cell is empty). A ``park_id`` key gives the park's latest
    configuration (the one standing now); a ``config_id`` key
    (``fence_configurations``) gives that configuration."""
    table: dict[str, tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]] = {}
    for c in fence_configurations():  # sorted by first date: the latest overwrites
        arrays = (c["spray_angle_deg"], c["distance_ft"], c["height_ft"])
        table[c["config_id"]] = arrays
        table[c["park_id"]] = arrays
    return table


def fence_config(park: ArrayLike, game_date: ArrayLike) -> NDArray[np.object_]:
    """The fence configuration standing at each park on each date.

    Parameters
    ----------
    park : str or array_like of str
        ``park_id`` (one, or one per date), e.g. from ``park_of``.
    game_date : array_like of datetime64 or str
        Game dates (``YYYY-MM-DD``).

    Returns
    -------
    ndarray of object
        ``config_id`` per row (accepted by ``fence`` and, as the ``park`` argument, by
        ``mcbat.statcast.home_runs.home_run_call``); None where the park has no fence
        or no configuration stood on that date (or the date is missing).
    """
    dates = _dates(game_date)
    ids, dates = np.broadcast_arrays(np.asarray(park, dtype=object), dates)
    out = np.full(ids.shape, None, dtype=object)
    for c in fence_configurations():
        rows = ((ids == c["park_id"]) & (dates >= c["first_date"])
                & (dates <= c["last_date"]))
        out[rows] = c["config_id"]
    return out


def fence(park: ArrayLike, spray_angle_deg: ArrayLike, game_date: ArrayLike | None = None
          ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Outfield fence distance and height along a spray angle.

    Distance is interpolated linearly in spray angle between the table's points and held
    constant beyond the outermost ones; height is piecewise constant, the height of the
    nearest point that has one (walls change height in steps). Spray angle as Statcast:
    ``atan2(x, y)`` with x towards first base, y towards centre field, so the LF line is
    -45 deg and the RF line +45 deg.

    Parameters
    ----------
    park : str or array_like of str
        ``park_id`` (one, or one per angle), e.g. from ``park_of``, or a ``config_id``
        from ``fence_config``. Without ``game_date`` a ``park_id`` means the park's
        latest configuration (the fences standing now).
    spray_angle_deg : float or array_like
        Spray angles (deg).
    game_date : array_like of datetime64 or str, optional
        Game dates; when given, each row gets the configuration standing at its park on
        that date (``fence_config``), and NaN where none did.

    Returns
    -------
    distance_ft, height_ft : ndarray of float
        NaN for an unknown park or NaN angle; height NaN where the park has no sourced
        height.

    Raises
    ------
    InputError
        When a single ``park`` is not in the fence table.
    """
    angles = np.asarray(spray_angle_deg, dtype=float)
    table = fences()
    ids = np.asarray(park, dtype=object)
    if ids.ndim == 0:
        if ids.item() not in table:
            raise InputError("park", f"no fence for park {ids.item()!r}; known: "
                             + ", ".join(sorted(k for k in table if "@" not in k)))
        ids = np.full(angles.shape, ids.item(), dtype=object)
    if game_date is not None:
        ids, dates = np.broadcast_arrays(ids, _dates(game_date))
        ids = fence_config(ids, dates)
    ids, angles = np.broadcast_arrays(ids, angles)
    dist = np.full(angles.shape, np.nan)
    height = np.full(angles.shape, np.nan)
    for pid in set(ids.ravel()) & set(table):
        a, d, h = table[pid]
        rows = ids == pid
        x = angles[rows]
        ok = ~np.isnan(d)
        dist[rows] = np.interp(x, a[ok], d[ok])
        has = ~np.isnan(h)
        if has.any():
            ah, hh = a[has], h[has]
            nearest = np.abs(x[:, None] - ah[None, :]).argmin(axis=1)
            height[rows] = hh[nearest]
        dist[rows] = np.where(np.isnan(x), np.nan, dist[rows])
        height[rows] = np.where(np.isnan(x), np.nan, height[rows])
    return dist, height
