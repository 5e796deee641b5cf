"""The normal game-time air of each park and month, from the recorded weather of real games.

Run:  .venv/bin/python -m validation park_climate WEATHER.csv [--write data/park_climate.csv]
          [--min-games 8]

``WEATHER.csv`` is a per-game weather table (``docs/parks-and-weather.md``), e.g. the one
``python -m validation retrosheet_weather`` writes from Retrosheet's event files. Each game
is placed in its park (:func:`mcbat.statcast.parks.park_of`, by home team and date); per
park and calendar month (March-October) with at least ``--min-games`` games:

- ``roof_closed_share``: the share of the games played under a closed roof (Retrosheet's
  sky ``dome``); 0 for an open park, 1 for a dome;
- ``temperature_f``: the median game-time temperature of the games played with the roof
  open (of all games where none was), the "normal" game a park and month sees;
- ``games``: how many games the row rests on; ``relative_humidity`` is left empty (no
  per-game humidity is recorded: 50 % is assumed).

A month of March-October with fewer games (the season's first days in March, its last in
October) takes the row of the park's nearest month that has enough, with ``games`` 0 and
its ``source`` saying which month.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from mcbat.statcast import parks
from mcbat.statcast.weather import read_weather

HEADER = """\
# Normal game-time air per park and calendar month: the median recorded game-time temperature
# (degF) of the games played there with the roof open, and the share of its games played under
# a closed roof, from the per-game weather of every regular-season game of 2015-2023
# (Retrosheet's event files, converted by `python -m validation retrosheet_weather`; this table
# by `python -m validation park_climate`). relative_humidity empty: not recorded, 50 % assumed.
# The information used here was obtained free of charge from and is copyrighted by Retrosheet.
# Interested parties may contact Retrosheet at www.retrosheet.org.
"""


def climate_table(weather: pd.DataFrame, min_games: int = 8) -> pd.DataFrame:
    """Per park and month: ``temperature_f``, ``roof_closed_share``, ``games``."""
    dates = pd.to_datetime(weather["game_date"], errors="coerce")
    park = parks.park_of(weather["home_team"].to_numpy(dtype=object), dates.to_numpy())
    frame = pd.DataFrame({"park_id": park, "month": dates.dt.month,
                          "temperature": weather["temperature"].to_numpy(float),
                          "closed": (weather["roof"] == "closed").to_numpy(bool)})
    frame = frame[frame["park_id"].notna() & frame["month"].between(3, 10)
                  & np.isfinite(frame["temperature"])]
    rows = []
    for (park_id, month), games in frame.groupby(["park_id", "month"], sort=True):
        if len(games) < min_games:
            continue
        open_games = games[~games["closed"]]
        source = open_games if len(open_games) else games
        rows.append({"park_id": park_id, "month": int(month),
                     "temperature_f": round(float(np.median(source["temperature"])), 1),
                     "relative_humidity": "",
                     "roof_closed_share": round(float(games["closed"].mean()), 3),
                     "games": len(games), "station": "game-time records",
                     "source": "Retrosheet event files 2015-2023"})
    table = pd.DataFrame(rows)
    filled = []
    for park_id, months in table.groupby("park_id"):
        have = months.set_index("month")
        for month in range(3, 11):
            if month in have.index:
                continue
            nearest = min(have.index, key=lambda m: (abs(m - month), m))
            row = have.loc[nearest].to_dict()
            row.update(park_id=park_id, month=month, games=0,
                       source=f"as month {nearest} (fewer than {min_games} games in month "
                              f"{month})")
            filled.append(row)
    table = pd.concat([table, pd.DataFrame(filled)], ignore_index=True)
    return table.sort_values(["park_id", "month"], kind="stable").reset_index(drop=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("weather", metavar="WEATHER.csv")
    parser.add_argument("--write", default=None, metavar="CSV")
    parser.add_argument("--min-games", type=int, default=8)
    args = parser.parse_args(argv)
    table = climate_table(read_weather(args.weather), args.min_games)
    print(f"{len(table)} park-months of {table['park_id'].nunique()} parks "
          f"({int(table['games'].sum()):,} games)")
    pivot = table.pivot(index="park_id", columns="month", values="temperature_f")
    print(pivot.to_string(float_format=lambda v: f"{v:.0f}"))
    if args.write:
        Path(args.write).write_text(HEADER + table.to_csv(index=False))
        print(f"written to {args.write}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
