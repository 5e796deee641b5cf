"""The air of each Statcast row: the park's elevation, the game's weather (when a per-game
weather table is given) or the park's climate normal, the roof, and the wind in the field
frame.

The per-game weather table (CSV or Parquet, one row per game) is specified for users in
``docs/parks-and-weather.md``. Conventions: wind codes are Retrosheet's ``info,winddir``;
the field frame has x towards first base and y towards centre field (Statcast's
``spray_angle = atan2(x, y)``).
"""

from __future__ import annotations

import csv
import functools
import math
from collections.abc import Callable, Iterable
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mcbat.core.units import M_S_PER_MPH as MPH
from mcbat.errors import InputError
from mcbat.statcast import parks

if TYPE_CHECKING:
    import pandas as pd

_Floats = NDArray[np.float64]
_Index = int | np.integer[Any]  # a row number (numpy's, from flatnonzero)
_Fail = Callable[[str, _Index, str], NoReturn]

__all__ = ["CLIMATE_FILE", "INDOOR_HUMIDITY", "INDOOR_TEMPERATURE", "MPH", "STANDARD",
           "TEAM_ALIASES", "WIND_CODES", "air", "climate", "read_weather", "wind_vector"]

CLIMATE_FILE = "park_climate.csv"
"""m/s per mph."""
INDOOR_TEMPERATURE = 72.0
"""degF assumed under a dome or a closed roof."""
INDOOR_HUMIDITY = 50.0
"""% assumed under a dome or a closed roof."""
STANDARD = {"temperature": 70.0, "pressure": 29.92, "relative_humidity": 50.0}
"""The air assumed where nothing is known (degF, inHg at sea level, %)."""
_SIDE = math.sqrt(0.5)
WIND_CODES = {
    "tocf": (0.0, 1.0), "fromcf": (0.0, -1.0), "ltor": (1.0, 0.0), "rtol": (-1.0, 0.0),
    "tolf": (-_SIDE, _SIDE), "torf": (_SIDE, _SIDE),
    "fromlf": (_SIDE, -_SIDE), "fromrf": (-_SIDE, -_SIDE),
    "unknown": (math.nan, math.nan), "": (math.nan, math.nan),
}
"""Unit vectors (x to first base, y to centre field) the wind blows towards, per Retrosheet
code. ``tolf``/``torf`` blow out along the spray directions -45 deg and +45 deg (the foul
lines); ``fromlf``/``fromrf`` blow in along them."""

_RANGES = {"temperature": (-20.0, 130.0, "degF"), "wind_speed": (0.0, 100.0, "mph"),
           "pressure": (25.0, 32.5, "inHg"), "relative_humidity": (0.0, 100.0, "%")}
UNITS = {"game_pk": "id", "game_date": "date", "home_team": "code", "game_number": "1",
         "temperature": "degF", "wind_speed": "mph", "wind_direction": "code",
         "roof": "code (open, closed)", "pressure": "inHg (sea level)",
         "relative_humidity": "%"}


def wind_vector(direction_code: ArrayLike, speed_mph: ArrayLike) -> tuple[_Floats, _Floats]:
    """Wind velocity in the field frame from Retrosheet's direction code and a speed.

    Parameters
    ----------
    direction_code : str or array_like of str
        ``tocf``, ``tolf``, ``torf``, ``fromcf``, ``fromlf``, ``fromrf``, ``ltor``,
        ``rtol``, ``unknown`` or empty.
    speed_mph : float or array_like
        Wind speed (mph); NaN or negative (Retrosheet's -1) = unknown.

    Returns
    -------
    wind_x, wind_y : ndarray of float
        m/s, x towards first base, y towards centre field; 0 where the direction or the
        speed is unknown.

    Raises
    ------
    InputError
        For a code not in ``WIND_CODES``.
    """
    codes = np.asarray(direction_code, dtype=object)
    speed = np.asarray(speed_mph, dtype=float)
    codes, speed = np.broadcast_arrays(codes, speed)
    ux = np.zeros(codes.shape)
    uy = np.zeros(codes.shape)
    for i, code in np.ndenumerate(codes):
        key = "" if code is None or (isinstance(code, float) and math.isnan(code)) \
            else str(code).strip().lower()
        if key not in WIND_CODES:
            raise InputError("wind_direction", f"unknown wind code {code!r}; expected one "
                             "of " + ", ".join(k for k in WIND_CODES if k))
        ux[i], uy[i] = WIND_CODES[key]
    known = np.isfinite(ux) & np.isfinite(speed) & (speed >= 0)
    v = np.where(known, speed * MPH, 0.0)
    return np.where(known, ux * v, 0.0), np.where(known, uy * v, 0.0)


def read_weather(path: str | Path) -> pd.DataFrame:
    """Read and check a per-game weather table (CSV or Parquet).

    Parameters
    ----------
    path : str or Path
        The file; ``.parquet`` is read as Parquet, anything else as CSV.

    Returns
    -------
    DataFrame
        The columns of ``docs/parks-and-weather.md``: Retrosheet's unknown markers (0
        degF, -1 mph) and empty cells become NaN, codes lower case; ``attrs["units"]``.

    Raises
    ------
    InputError
        One line naming the file, the column and the line of the first bad cell: a
        missing key, a value out of range, an unknown wind or roof code, a game twice.
    """
    import pandas as pd

    path = Path(path)
    comments = 0  # leading "#" lines (a source's notice) before the header
    try:
        if path.suffix != ".parquet":
            with path.open(encoding="utf-8-sig") as text:
                for first in text:
                    if not first.startswith("#"):
                        break
                    comments += 1
        raw = (pd.read_parquet(path) if path.suffix == ".parquet"
               else pd.read_csv(path, dtype=str, keep_default_na=False, skiprows=comments,
                                encoding="utf-8-sig"))
    except (OSError, ValueError) as err:
        raise InputError("path", f"cannot read the weather table: {err}", str(path)) from None
    raw = raw.astype(str).replace({"nan": "", "None": "", "<NA>": ""})
    source = str(path)
    i: _Index  # a row number

    def line(i: _Index) -> _Index:
        return i + 2 + comments if path.suffix != ".parquet" else i + 1

    def fail(column: str, i: _Index, what: str) -> NoReturn:
        raise InputError(column, f"line {line(i)}: {what}", source)

    by_pk = "game_pk" in raw.columns
    by_date = all(c in raw.columns for c in ("game_date", "home_team", "game_number"))
    if not (by_pk or by_date):
        raise InputError("game_pk", "no game key: give game_pk or all of game_date, "
                         "home_team and game_number", source)
    for column in ("temperature", "wind_speed", "wind_direction", "roof"):
        if column not in raw.columns:
            raise InputError(column, "missing column", source)
    out = pd.DataFrame(index=raw.index)
    if by_pk:
        out["game_pk"] = _integers(raw["game_pk"], "game_pk", fail)
    if by_date:
        dates = pd.to_datetime(raw["game_date"], format="%Y-%m-%d", errors="coerce")
        for i in np.flatnonzero(dates.isna().to_numpy()):
            fail("game_date", i, f"not a YYYY-MM-DD date: {raw['game_date'].iloc[i]!r}")
        out["game_date"] = dates
        out["home_team"] = raw["home_team"].str.strip().str.upper()
        numbers = _integers(raw["game_number"], "game_number", fail)
        for i in np.flatnonzero(~np.isin(numbers, [0, 1, 2])):
            fail("game_number", i, f"{raw['game_number'].iloc[i]!r} is not 0, 1 or 2")
        out["game_number"] = numbers
    _numbers(raw, out, fail)
    _codes(raw, out, fail)
    keys = ["game_pk"] if by_pk else ["game_date", "home_team", "game_number"]
    dup = out.duplicated(subset=keys, keep="first").to_numpy()
    if dup.any():
        i = int(np.flatnonzero(dup)[0])
        fail(keys[0], i, "the same game twice (" + ", ".join(
            f"{k}={raw[k].iloc[i]}" for k in keys) + ")")
    out.attrs["units"] = {k: v for k, v in UNITS.items() if k in out.columns}
    return out.reset_index(drop=True)


def _numbers(raw: pd.DataFrame, out: pd.DataFrame, fail: _Fail) -> None:
    import pandas as pd

    for column, unknown in (("temperature", 0.0), ("wind_speed", -1.0),
                            ("pressure", None), ("relative_humidity", None)):
        if column not in raw.columns:
            out[column] = np.nan
            continue
        values = pd.to_numeric(raw[column].str.strip().replace("", "nan"), errors="coerce")
        for i in np.flatnonzero(values.isna().to_numpy() & (raw[column].str.strip() != "")
                                .to_numpy()):
            fail(column, i, f"not a number: {raw[column].iloc[i]!r}")
        if unknown is not None:
            values = values.where(values != unknown)
        lo, hi, unit = _RANGES[column]
        for i in np.flatnonzero(((values < lo) | (values > hi)).to_numpy()):
            fail(column, i, f"{values.iloc[i]:g} {unit} is outside [{lo:g}, {hi:g}]")
        out[column] = values.to_numpy(dtype=float)


def _codes(raw: pd.DataFrame, out: pd.DataFrame, fail: _Fail) -> None:
    winds = raw["wind_direction"].str.strip().str.lower()
    for i in np.flatnonzero(~winds.isin(list(WIND_CODES)).to_numpy()):
        fail("wind_direction", i, f"unknown wind code {raw['wind_direction'].iloc[i]!r}")
    out["wind_direction"] = winds.replace("", "unknown")
    roofs = raw["roof"].str.strip().str.lower()
    for i in np.flatnonzero(~roofs.isin(["open", "closed", ""]).to_numpy()):
        fail("roof", i, f"unknown roof {raw['roof'].iloc[i]!r}; expected open, closed or "
             "empty")
    out["roof"] = roofs


def _integers(column: pd.Series, name: str, fail: _Fail) -> NDArray[np.int64]:
    import pandas as pd

    values = pd.to_numeric(column.str.strip(), errors="coerce")
    bad = values.isna().to_numpy() | (values % 1 != 0).to_numpy()
    for i in np.flatnonzero(bad):
        fail(name, i, f"not an integer: {column.iloc[i]!r}")
    return values.to_numpy(dtype=np.int64)


@functools.cache
def _climate_rows() -> dict[tuple[str, int], tuple[float, float, float]]:
    text = resources.files("mcbat.data").joinpath(CLIMATE_FILE).read_text(encoding="utf-8")
    table: dict[tuple[str, int], tuple[float, float, float]] = {}
    for row in csv.DictReader(line for line in text.splitlines()
                              if line.strip() and not line.startswith("#")):
        rh = row["relative_humidity"].strip()
        table[(row["park_id"].strip(), int(row["month"]))] = (
            float(row["temperature_f"]), float(rh) if rh else math.nan,
            float(row["roof_closed_share"]))
    return table


def climate(park_ids: ArrayLike, months: ArrayLike) -> tuple[_Floats, _Floats, _Floats]:
    """Normal game-time temperature (degF), relative humidity (%) and the share of games
    played under a closed roof, per park and month, from ``data/park_climate.csv``; NaN
    where the table has no row."""
    table = _climate_rows()
    ids = np.asarray(park_ids, dtype=object)
    months = np.asarray(months, dtype=float)
    temp = np.full(ids.shape, np.nan)
    rh = np.full(ids.shape, np.nan)
    closed = np.full(ids.shape, np.nan)
    for i, (pid, m) in enumerate(zip(ids.ravel(), months.ravel())):
        if np.isfinite(m) and (pid, int(m)) in table:
            temp.flat[i], rh.flat[i], closed.flat[i] = table[(pid, int(m))]
    return temp, rh, closed


def air(table: pd.DataFrame, weather: pd.DataFrame | str | Path | None = None
        ) -> pd.DataFrame:
    """The air of each row of a tidy Statcast table.

    Parameters
    ----------
    table : DataFrame
        With ``game_pk``, ``game_date``, ``home_team`` (``mcbat.statcast.read``'s output).
    weather : DataFrame or str or Path, optional
        A per-game weather table (``read_weather`` is applied to a path).

    Returns
    -------
    DataFrame
        Aligned with ``table``: ``park``, ``elevation`` (ft), ``temperature`` (degF),
        ``pressure`` (inHg, sea-level corrected), ``relative_humidity`` (%), ``wind_x``,
        ``wind_y`` (m/s, x to first base, y to centre field), ``roof_closed`` (bool),
        ``air_source`` (``weather``, ``climate``, ``indoor``, ``standard``) and
        ``wind_source`` (``weather``, ``indoor``, ``none``). A weather row wins over the
        climate; a dome or a closed roof means indoor air and no wind whatever the weather
        row says; an unknown wind is no wind; a retractable roof of unknown state is as it
        was in most of that park's games of the month (closed where that is unknown).
        ``attrs["units"]`` gives the units.
    """
    import pandas as pd

    n = len(table)
    dates = pd.to_datetime(table["game_date"], errors="coerce")
    park = parks.park_of(table["home_team"].to_numpy(dtype=object), dates.to_numpy())
    roof_kind = parks.park_value(park, "roof")
    out = pd.DataFrame(index=table.index)
    out["park"] = park
    out["elevation"] = parks.park_value(park, "elevation_ft")
    temp, rh, closed_share = climate(park, dates.dt.month.to_numpy(dtype=float))
    src = np.where(np.isfinite(temp), "climate", "standard").astype(object)
    temp = np.where(np.isfinite(temp), temp, STANDARD["temperature"])
    rh = np.where(np.isfinite(rh), rh, STANDARD["relative_humidity"])
    pressure = np.full(n, STANDARD["pressure"])
    wx = np.zeros(n)
    wy = np.zeros(n)
    wsrc = np.full(n, "none", dtype=object)
    roof_state = np.full(n, "", dtype=object)

    if weather is not None:
        w = read_weather(weather) if isinstance(weather, (str, Path)) else weather
        idx = _match(table, dates, w)
        hit = idx >= 0
        if hit.any():
            rows = w.iloc[idx[hit]]
            wt = rows["temperature"].to_numpy(dtype=float)
            temp[hit] = np.where(np.isfinite(wt), wt, temp[hit])
            src[hit] = np.where(np.isfinite(wt), "weather", src[hit])
            for column, target in (("pressure", pressure), ("relative_humidity", rh)):
                if column in rows:
                    v = rows[column].to_numpy(dtype=float)
                    target[hit] = np.where(np.isfinite(v), v, target[hit])
            x, y = wind_vector(rows["wind_direction"].to_numpy(dtype=object),
                               rows["wind_speed"].to_numpy(dtype=float))
            wx[hit], wy[hit] = x, y
            known = (rows["wind_direction"].to_numpy(dtype=object) != "unknown") & \
                np.isfinite(rows["wind_speed"].to_numpy(dtype=float))
            wsrc[hit] = np.where(known, "weather", "none")
            roof_state[hit] = rows["roof"].to_numpy(dtype=object)

    # A retractable roof of unknown state is as it most often was in that park and month
    # (the climate table's share of games under a closed roof), closed where that is
    # unknown too.
    usually_closed = ~(closed_share < 0.5)
    closed = (roof_kind == "dome") | (roof_state == "closed") | \
        ((roof_kind == "retractable") & (roof_state != "open") & usually_closed)
    temp = np.where(closed, INDOOR_TEMPERATURE, temp)
    rh = np.where(closed, INDOOR_HUMIDITY, rh)
    src = np.where(closed, "indoor", src)
    wx = np.where(closed, 0.0, wx)
    wy = np.where(closed, 0.0, wy)
    wsrc = np.where(closed, "indoor", wsrc)
    unknown_park = np.array([p is None for p in park], dtype=bool)
    src = np.where(unknown_park, "standard", src)
    out["temperature"] = temp
    out["pressure"] = pressure
    out["relative_humidity"] = rh
    out["wind_x"] = wx
    out["wind_y"] = wy
    out["roof_closed"] = closed.astype(bool)
    out["air_source"] = src
    out["wind_source"] = wsrc
    out.attrs["units"] = {"park": "id", "elevation": "ft", "temperature": "degF",
                          "pressure": "inHg (sea level)", "relative_humidity": "%",
                          "wind_x": "m/s", "wind_y": "m/s", "roof_closed": "bool",
                          "air_source": "code", "wind_source": "code"}
    return out


#: Team codes that name the same club (Savant wrote Arizona as ARI until 2022, AZ since).
TEAM_ALIASES = {"ARI": "AZ"}


def _team(codes: Iterable[str]) -> NDArray[np.object_]:
    return np.array([TEAM_ALIASES.get(c, c) for c in codes], dtype=object)


def _match(table: pd.DataFrame, dates: pd.Series, w: pd.DataFrame) -> NDArray[np.int64]:
    """Index of each Statcast row's weather row (-1 for none)."""
    import pandas as pd

    n = len(table)
    idx = np.full(n, -1, dtype=np.int64)
    if "game_pk" in w.columns:
        where = {int(pk): i for i, pk in enumerate(w["game_pk"])}
        pks = pd.to_numeric(table["game_pk"], errors="coerce").to_numpy(dtype=float)
        for r, pk in enumerate(pks):
            if np.isfinite(pk):
                idx[r] = where.get(int(pk), -1)
    if {"game_date", "home_team", "game_number"} <= set(w.columns):
        key = {(d.strftime("%Y-%m-%d"), t, int(g)): i for i, (d, t, g) in enumerate(
            zip(w["game_date"], _team(w["home_team"]), w["game_number"]))}
        frame = pd.DataFrame({"date": dates.dt.strftime("%Y-%m-%d"),
                              "team": _team(table["home_team"].to_numpy(dtype=object)),
                              "pk": pd.to_numeric(table["game_pk"], errors="coerce")})
        # doubleheaders: the lower game_pk of a date and home team is game 1
        games = frame.dropna().drop_duplicates().sort_values("pk")
        count = games.groupby(["date", "team"])["pk"].transform("size")
        order = games.groupby(["date", "team"]).cumcount() + 1
        number = {(d, t, p): (0 if c == 1 else o) for d, t, p, c, o in zip(
            games["date"], games["team"], games["pk"], count, order)}
        for r, (d, t, p) in enumerate(zip(frame["date"], frame["team"], frame["pk"])):
            if idx[r] >= 0 or (d, t, p) not in number:
                continue
            g = number[(d, t, p)]
            found = key.get((d, t, g), -1)
            if found < 0 and g == 0:
                found = key.get((d, t, 1), -1)
            idx[r] = found
    return idx
