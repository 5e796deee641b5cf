"""Game-time weather of every game in Retrosheet event files, as a per-game table.

Reads Retrosheet play-by-play event files (``*.EVA``, ``*.EVN``: one per team and season,
as in the ``event/regular`` folder Retrosheet publishes) and writes one row per game with
the weather the official scorer recorded: the ``info,temp``, ``info,winddir``,
``info,windspeed`` and ``info,sky`` records of each game. The table follows the shared
per-game weather format: the key ``game_date``, ``home_team`` (Statcast's code) and
``game_number`` (0 a single game, 1 and 2 the games of a doubleheader), then
``temperature`` (degF), ``wind_speed`` (mph), ``wind_direction`` (Retrosheet's codes) and
``roof``::

    python -m validation retrosheet_weather EVENT_DIR [EVENT_DIR ...] --out FILE.csv

Retrosheet writes an unknown temperature as 0 and an unknown wind speed as -1; both become
empty cells. ``info,sky,dome`` means a closed roof; any other recorded sky (sunny, cloudy,
overcast, night, ...) means the game was played in the open (an open-air park or an open
retractable roof); an unknown or missing sky leaves ``roof`` empty. A few Retrosheet
columns follow the shared ones: ``retrosheet_game_id``, ``site`` (Retrosheet's park code),
``sky`` and ``daynight``.

Retrosheet's team codes become Statcast's (``NYA`` -> ``NYY``, ``OAK`` -> ``ATH`` from 2025,
see :data:`TEAM_CODES`); a code outside the table is an error that names it.

The information used here was obtained free of charge from and is copyrighted by
Retrosheet. Interested parties may contact Retrosheet at www.retrosheet.org.
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

from mcbat.errors import InputError

IN_ALL = False  # needs event files of its own

#: Retrosheet team code -> Statcast's (Baseball Savant's ``home_team``), 2015-2025 clubs.
#: The Athletics are ``OAK`` in Statcast through 2024 and ``ATH`` from 2025 (see
#: :func:`statcast_team`); Retrosheet's own code for them in 2025 is accepted too.
TEAM_CODES = {
    "ANA": "LAA", "ARI": "AZ", "ATL": "ATL", "BAL": "BAL", "BOS": "BOS", "CHA": "CWS",
    "CHN": "CHC", "CIN": "CIN", "CLE": "CLE", "COL": "COL", "DET": "DET", "HOU": "HOU",
    "KCA": "KC", "LAN": "LAD", "MIA": "MIA", "MIL": "MIL", "MIN": "MIN", "NYA": "NYY",
    "NYN": "NYM", "OAK": "OAK", "ATH": "ATH", "PHI": "PHI", "PIT": "PIT", "SDN": "SD",
    "SEA": "SEA", "SFN": "SF", "SLN": "STL", "TBA": "TB", "TEX": "TEX", "TOR": "TOR",
    "WAS": "WSH",
}

#: Retrosheet's ``info,winddir`` codes, kept as they are.
WIND_DIRECTIONS = ("tocf", "tolf", "torf", "fromcf", "fromlf", "fromrf", "ltor", "rtol",
                   "unknown")

#: ``info,sky`` values that say the sky was seen: the game was played in the open.
OPEN_SKIES = ("sunny", "cloudy", "overcast", "night")

COLUMNS = ("game_date", "home_team", "game_number", "temperature", "wind_speed",
           "wind_direction", "roof", "retrosheet_game_id", "site", "sky", "daynight")

NOTICE = ("The information used here was obtained free of charge from and is copyrighted "
          "by Retrosheet. Interested parties may contact Retrosheet at www.retrosheet.org.")


def statcast_team(code: str, season: int, source: str | None = None) -> str:
    """Statcast's code of the club Retrosheet calls ``code`` in ``season``.

    Parameters
    ----------
    code : str
        Retrosheet team code (``info,hometeam``), e.g. ``"NYA"``.
    season : int
        The game's year; the Athletics are ``OAK`` through 2024 and ``ATH`` from 2025.
    source : str, optional
        File name for the error message.

    Returns
    -------
    str
        Statcast's code, e.g. ``"NYY"``.

    Raises
    ------
    InputError
        ``code`` is not a 2015-2025 club.
    """
    try:
        team = TEAM_CODES[code]
    except KeyError:
        raise InputError("info,hometeam", f"unknown Retrosheet team code {code!r}",
                         source) from None
    if team in ("OAK", "ATH"):
        return "ATH" if season >= 2025 else "OAK"
    return team


def _integer(value: str, field: str, source: str | None) -> int:
    try:
        return int(value)
    except ValueError:
        raise InputError(field, f"not an integer: {value!r}", source) from None


def _game_row(game_id: str, info: dict, source: str | None) -> dict:
    """One output row from a game's ``info`` records."""
    for key in ("date", "hometeam"):
        if not info.get(key):
            raise InputError(f"info,{key}", f"missing in game {game_id}", source)
    date = info["date"]
    parts = date.split("/")
    if len(parts) != 3 or not all(p.isdigit() for p in parts):
        raise InputError("info,date", f"not YYYY/MM/DD: {date!r} (game {game_id})", source)
    year, month, day = (int(p) for p in parts)
    number = _integer(info.get("number", "0") or "0", "info,number", source)
    if number not in (0, 1, 2):
        raise InputError("info,number", f"not 0, 1 or 2: {number} (game {game_id})", source)

    temperature = ""
    if info.get("temp", "") != "":
        t = _integer(info["temp"], "info,temp", source)
        temperature = "" if t == 0 else t  # Retrosheet: 0 = unknown
    wind_speed = ""
    if info.get("windspeed", "") != "":
        w = _integer(info["windspeed"], "info,windspeed", source)
        if w < -1:
            raise InputError("info,windspeed", f"negative: {w} (game {game_id})", source)
        wind_speed = "" if w == -1 else w  # Retrosheet: -1 = unknown
    direction = info.get("winddir", "").strip().lower()
    if direction not in ("",) + WIND_DIRECTIONS:
        raise InputError("info,winddir", f"unknown code {direction!r} (game {game_id})",
                         source)
    sky = info.get("sky", "").strip().lower()
    roof = "closed" if sky == "dome" else "open" if sky in OPEN_SKIES else ""
    return {
        "game_date": f"{year:04d}-{month:02d}-{day:02d}",
        "home_team": statcast_team(info["hometeam"], year, source),
        "game_number": number, "temperature": temperature, "wind_speed": wind_speed,
        "wind_direction": direction, "roof": roof, "retrosheet_game_id": game_id,
        "site": info.get("site", ""), "sky": sky, "daynight": info.get("daynight", ""),
    }


def read_event_file(path) -> list[dict]:
    """The weather rows of every game in one Retrosheet event file.

    Parameters
    ----------
    path : str or Path
        An event file (``2019NYA.EVA``). Only its ``id`` and ``info`` records are read.

    Returns
    -------
    list of dict
        One dict per game, with the keys of :data:`COLUMNS`; temperature in degF and wind
        speed in mph (empty string when Retrosheet gives them as unknown).

    Raises
    ------
    InputError
        A game lacks its date or home team, or a record has a malformed value.
    """
    path = Path(path)
    source = str(path)
    rows, game_id, info = [], None, {}
    with open(path, encoding="latin-1", newline="") as handle:
        for record in csv.reader(handle):
            if not record:
                continue
            kind = record[0].strip()
            if kind == "id":
                if game_id is not None:
                    rows.append(_game_row(game_id, info, source))
                game_id, info = record[1].strip() if len(record) > 1 else "", {}
            elif kind == "info" and game_id is not None and len(record) >= 2:
                info[record[1].strip()] = record[2].strip() if len(record) > 2 else ""
    if game_id is not None:
        rows.append(_game_row(game_id, info, source))
    return rows


def event_files(paths) -> list[Path]:
    """The ``*.EVA``/``*.EVN`` files under each directory of ``paths`` (a file is taken as
    it is), sorted by name."""
    found = []
    for p in map(Path, paths):
        if p.is_dir():
            found += [f for f in p.iterdir() if f.suffix.upper() in (".EVA", ".EVN")]
        elif p.is_file():
            found.append(p)
        else:
            raise InputError("EVENT_DIR", f"no such file or directory: {str(p)!r}")
    return sorted(found, key=lambda f: f.name)


def weather_table(paths) -> list[dict]:
    """Every game of the event files under ``paths``, sorted by date, home team and game
    number. Raises :class:`InputError` if a game appears twice."""
    rows = [row for f in event_files(paths) for row in read_event_file(f)]
    rows.sort(key=lambda r: (r["game_date"], r["home_team"], r["game_number"]))
    seen = set()
    for r in rows:
        key = (r["game_date"], r["home_team"], r["game_number"])
        if key in seen:
            raise InputError("retrosheet_game_id",
                             f"game {r['retrosheet_game_id']} appears twice")
        seen.add(key)
    return rows


def write_table(rows, out) -> None:
    """Write the rows as CSV with the header of :data:`COLUMNS`."""
    with open(out, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("event_dirs", nargs="+", metavar="EVENT_DIR",
                        help="folders of Retrosheet event files (*.EVA, *.EVN), or files")
    parser.add_argument("--out", required=True, type=Path, metavar="FILE",
                        help="the CSV to write")
    args = parser.parse_args(argv)
    try:
        rows = weather_table(args.event_dirs)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    write_table(rows, args.out)
    known = sum(r["temperature"] != "" for r in rows)
    seasons = sorted({r["game_date"][:4] for r in rows})
    print(f"{len(rows)} games ({', '.join(seasons)}), {known} with a temperature: "
          f"{args.out}")
    return 0
