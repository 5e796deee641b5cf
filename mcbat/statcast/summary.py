"""The counts ``mcbat statcast`` prints of a tidy table, and the check of the attack
direction's sign on the user's own data."""

from __future__ import annotations

import numpy as np

from mcbat.statcast.plays import balls_in_play
from mcbat.statcast.reader import UNITS

__all__ = ["attack_direction_check", "summarize"]


def summarize(df):
    """The counts ``mcbat statcast`` prints, as a JSON-ready dict.

    Keys: ``rows``, ``seasons`` (sorted), ``pitch_types`` (count per type, most common
    first; ``"(none)"`` for rows without one), ``balls_in_play``, ``with_distance``
    (``hit_distance_sc`` measured), ``with_bat_tracking`` (``bat_speed`` measured),
    ``with_launch`` (balls in play with launch speed and angle), ``plate`` (median and
    standard deviation of the plate speed and approach angles per pitch type),
    ``attack_direction_check`` (see ``docs/statcast.md``), ``units`` and the reader's
    report (``missing_columns``, ``non_numeric``, ``elevation_missing``,
    ``unknown_home_teams``, ``duplicate_columns``, ``duplicate_pitches``) and ``left_out``
    (rows the reader left out, by reason).
    """
    seasons = sorted({int(y) for y in df["game_year"].dropna()})
    types = df["pitch_type"].fillna("(none)").value_counts()
    bip = balls_in_play(df)
    launch = bip & df["launch_speed"].notna().to_numpy() & df["launch_angle"].notna().to_numpy()
    plate = {}
    for kind, rows in df.groupby(df["pitch_type"].fillna("(none)")):
        entry = {"pitches": int(len(rows))}
        for column in ("pitch_speed", "vertical_approach_angle",
                       "horizontal_approach_angle"):
            values = rows[column].dropna()
            entry[column] = ({"median": float(values.median()),
                              "sd": float(values.std(ddof=1)) if len(values) > 1 else None}
                             if len(values) else None)
        plate[str(kind)] = entry
    report = dict(df.attrs.get("statcast", {}))
    out = {
        "rows": int(len(df)),
        "seasons": seasons,
        "pitch_types": {str(k): int(v) for k, v in types.items()},
        "balls_in_play": int(bip.sum()),
        "with_launch": int(launch.sum()),
        "with_distance": int(df["hit_distance_sc"].notna().sum()),
        "with_bat_tracking": int(df["bat_speed"].notna().sum()),
        "plate": plate,
        "attack_direction_check": attack_direction_check(df),
        "units": dict(UNITS),
    }
    out["left_out"] = dict(report.get("left_out", {}))
    for key in ("source", "missing_columns", "non_numeric", "out_of_range",
                "elevation_missing", "unknown_home_teams", "duplicate_columns",
                "duplicate_pitches"):
        if key in report:
            out[key] = report[key]
    return out


def attack_direction_check(df, minimum=20):
    """Whether the swing's attack direction agrees in sign with where the ball went.

    Among balls in play with both an attack direction and a spray angle, the correlation
    between ``attack_direction`` and the spray angle towards the batter's opposite field
    (``spray_angle`` for a right-handed batter, ``-spray_angle`` for a left-handed one).
    A clearly positive value confirms the convention of ``docs/statcast.md`` (positive
    towards the opposite field) on the user's own data. None with fewer than ``minimum``
    such rows.
    """
    sign = np.where(df["handedness"].to_numpy() == "L", -1.0, 1.0)
    opposite = sign * df["spray_angle"].to_numpy(dtype=float)
    attack = df["attack_direction"].to_numpy(dtype=float)
    rows = balls_in_play(df) & np.isfinite(opposite) & np.isfinite(attack)
    if rows.sum() < minimum:
        return None
    r = float(np.corrcoef(attack[rows], opposite[rows])[0, 1])
    return {"rows": int(rows.sum()), "correlation": r}
