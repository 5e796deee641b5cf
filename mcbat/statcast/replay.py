"""What if? Every batted ball of a Savant export flown again under other conditions.

Each ball in play with a measured launch (``launch_speed``, ``launch_angle``, and a spray
angle from its hit coordinates) is flown twice with the regulation ball and Nathan's
average spin model (``mcbat.statcast.spin``):

- **as it was**: its own park, its season's ball (``mcbat.study.flight.season_scales``)
  and its own air (``mcbat.statcast.weather.air``: a weather table's game row when one
  is given, with the recorded wind at the season table's scale; else the park's climate
  normal for the month; indoor air under a closed roof);
- **replayed**: the same, with what the ``Conditions`` change: another park (its
  elevation, roof, fences and climate normal for the ball's month; a game's recorded
  weather belongs to its own park and is not carried over), a temperature, a wind (at full
  strength; none under a closed roof), a drag scale in place of the season's.

Both flights go to the ground (the carry); each is called a home run or not against the
fences of the park it was flown in (``mcbat.statcast.home_runs.home_run_call``). The
difference is the model's: what the conditions change for the same launch.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any, cast

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL
from mcbat.core.units import M_PER_FT, M_S_PER_MPH, RAD_PER_DEG, RAD_S_PER_RPM
from mcbat.errors import InputError
from mcbat.solving import FlightStatus
from mcbat.statcast import parks, weather
from mcbat.statcast.home_runs import home_run_call
from mcbat.statcast.launch import launch_spray
from mcbat.statcast.reader import balls_in_play
from mcbat.study.flight import (
    FlightSettings,
    flight_seasons,
    fly_launches,
    season_scales,
    season_wind_scale,
)

__all__ = ["OUTPUT_UNITS", "Conditions", "replay", "replay_summary"]

BALL = BALL_PRESETS[DEFAULT_BALL]
SETTINGS = FlightSettings()

OUTPUT_UNITS = {
    "game_pk": "id", "at_bat_number": "1", "pitch_number": "1", "game_date": "date",
    "home_team": "code", "batter": "id", "events": "code", "bb_type": "code",
    "launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
    "launch_spray_angle": "deg", "hit_distance_sc": "ft", "backspin": "rpm", "sidespin": "rpm",
    "park": "id", "temperature": "degF", "drag_scale": "1",
    "predicted_distance": "ft", "landing_x": "ft", "landing_y": "ft",
    "fence_distance": "ft", "fence_height": "ft", "home_run": "bool",
    "home_run_probability": "1", "actual_park": "id", "actual_temperature": "degF",
    "actual_distance": "ft", "actual_home_run": "bool", "actual_home_run_probability": "1",
    "change": "ft",
}
"""Columns of the replay table and their units."""


@dataclasses.dataclass(frozen=True)
class Conditions:
    """What a replay changes (None: as it was).

    Parameters
    ----------
    park : str, optional
        Statcast's ``home_team`` code of the park to fly at (``COL``: Coors Field); the
        park that team played in on each ball's date.
    temperature : float, optional
        degF, every ball.
    wind_speed : float, optional
        mph, with ``wind_direction`` (Retrosheet's codes: ``tocf``, ``fromcf``, ``ltor``,
        ``rtol``, ``tolf``, ``torf``, ``fromlf``, ``fromrf``), at full strength.
    drag_scale : float, optional
        Nathan's spin-free drag times this, instead of each season's.
    """

    park: str | None = None
    temperature: float | None = None
    wind_speed: float | None = None
    wind_direction: str | None = None
    drag_scale: float | None = None

    def __post_init__(self) -> None:
        if self.park is not None and not any(p["home_team"] == self.park
                                             for p in parks.parks()):
            codes = sorted({p["home_team"] for p in parks.parks()})
            raise InputError("park", f"unknown park code {self.park!r}: one of Statcast's "
                             f"home_team codes ({', '.join(codes)})")
        if self.temperature is not None and not -20.0 <= self.temperature <= 130.0:
            raise InputError("temperature", f"must lie in [-20, 130] degF, got "
                             f"{self.temperature:g}")
        if (self.wind_speed is None) != (self.wind_direction is None):
            raise InputError("wind_direction" if self.wind_direction is None
                             else "wind_speed", "give the wind's speed and direction together")
        if self.wind_speed is not None:
            if not 0.0 <= self.wind_speed <= 100.0:
                raise InputError("wind_speed", f"must lie in [0, 100] mph, got "
                                 f"{self.wind_speed:g}")
            if self.wind_direction not in weather.WIND_CODES:
                raise InputError("wind_direction", f"must be one of "
                                 f"{', '.join(weather.WIND_CODES)}, got "
                                 f"{self.wind_direction!r}")
        if self.drag_scale is not None and not 0.2 <= self.drag_scale <= 3.0:
            raise InputError("drag_scale", f"must lie in [0.2, 3], got {self.drag_scale:g}")

    def describe(self) -> str:
        """The conditions in words."""
        parts = [f"at {self.park}" if self.park else "in its own park"]
        if self.temperature is not None:
            parts.append(f"{self.temperature:g} degF")
        if self.wind_speed is not None:
            parts.append(f"wind {self.wind_speed:g} mph {self.wind_direction}")
        if self.drag_scale is not None:
            parts.append(f"drag scale {self.drag_scale:g}")
        return ", ".join(parts)


def _batted(table: pd.DataFrame) -> pd.DataFrame:
    numbers = np.column_stack([pd.to_numeric(table[c], errors="coerce").to_numpy(float)
                               for c in ("launch_speed", "launch_angle", "spray_angle")])
    side = table["handedness"].astype("string").isin(("R", "L")).fillna(False).to_numpy(bool)
    keep = balls_in_play(table) & np.isfinite(numbers).all(axis=1) & side & (
        numbers[:, 0] > 0)
    batted: pd.DataFrame = table.loc[keep].reset_index(drop=True)
    return batted


def _per_ball(air: pd.DataFrame, drag: ArrayLike) -> dict[str, ArrayLike]:
    return {"temperature": (air["temperature"].to_numpy(float) - 32.0) / 1.8 + 273.15,
            "pressure": air["pressure"].to_numpy(float) * 3386.389,
            "relative_humidity": air["relative_humidity"].to_numpy(float),
            "elevation": air["elevation"].to_numpy(float) * M_PER_FT,
            "wind_x": air["wind_x"].to_numpy(float),
            "wind_y": air["wind_y"].to_numpy(float), "drag_scale": drag}


def _scatter(game_year: ArrayLike) -> NDArray[np.float64]:
    """Each ball's season's scatter of the carry about the model (ft): the season table's
    ``sigma_ft``, the median over seasons for a season it lacks."""
    seasons = flight_seasons()
    typical = float(np.median([r["sigma_ft"] for r in seasons.values()])) if seasons else 15.0
    years = np.asarray(game_year, float)
    return np.array([seasons[int(y)]["sigma_ft"] if np.isfinite(y) and int(y) in seasons
                     else typical for y in years])


def _fly(balls: pd.DataFrame, air: pd.DataFrame, drag: ArrayLike, backspin: NDArray[np.float64],
         sidespin: NDArray[np.float64], park_ids: ArrayLike
         ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], pd.DataFrame]:
    """Carry, landing point (ft) and home-run call of ``balls`` in ``air``."""
    per_ball = _per_ball(air, drag)
    launch = (balls["launch_speed"].to_numpy(float), balls["launch_angle"].to_numpy(float),
              balls["spray_angle"].to_numpy(float))
    out, status = fly_launches(SETTINGS, BALL.mass, BALL.radius, launch[0] * M_S_PER_MPH,
                               launch[1] * RAD_PER_DEG, launch[2] * RAD_PER_DEG,
                               backspin * RAD_S_PER_RPM, sidespin * RAD_S_PER_RPM,
                               per_ball=per_ball)
    ok = status == FlightStatus.OK
    call = home_run_call(*launch, backspin, sidespin, park_ids, per_ball=per_ball,
                         game_date=pd.to_datetime(balls["game_date"]).to_numpy(),
                         scatter_ft=_scatter(balls["game_year"]))
    return (np.where(ok, out["hit_distance"] / M_PER_FT, np.nan),
            np.where(ok, out["landing_x"] / M_PER_FT, np.nan),
            np.where(ok, out["landing_y"] / M_PER_FT, np.nan), call)


def replay(table: pd.DataFrame, conditions: Conditions | None = None, *,
           weather_table: pd.DataFrame | str | Path | None = None) -> pd.DataFrame:
    """Every batted ball of ``table`` (``mcbat.statcast.read``) as it was and under
    ``conditions`` (module docstring).

    Returns
    -------
    pandas.DataFrame
        One row per batted ball: identifiers, the launch (``spray_angle`` as measured, where
        it came down; ``launch_spray_angle`` the direction it left the bat in), the
        measured ``hit_distance_sc``, the spin flown, then the replay (``park``,
        ``temperature``, ``drag_scale``,
        ``predicted_distance``, ``landing_x``, ``landing_y``, ``fence_distance``,
        ``fence_height``, ``home_run``) and the ball as it was (``actual_park``,
        ``actual_temperature``, ``actual_distance``, ``actual_home_run``) and ``change``
        (replayed minus as it was, ft). Units in ``attrs["units"]``
        (``OUTPUT_UNITS``), the conditions in ``attrs["conditions"]``.
    """
    conditions = Conditions() if conditions is None else conditions
    balls = _batted(table)
    if balls.empty:
        raise InputError("launch_speed", "no ball in play with a launch speed, launch angle "
                         "and hit coordinates: nothing to replay")
    season_drag, _, _ = season_scales(balls["game_year"])
    wind_scale = season_wind_scale()

    own = weather.air(balls, weather_table)
    own = own.assign(wind_x=own["wind_x"] * wind_scale, wind_y=own["wind_y"] * wind_scale)
    landing = balls["spray_angle"].to_numpy(float)
    spray, backspin, sidespin = launch_spray(
        balls["launch_speed"], balls["launch_angle"], landing, balls["handedness"],
        per_ball=_per_ball(own, season_drag), settings=SETTINGS, ball=BALL)
    balls = balls.assign(spray_angle=spray)
    actual = _fly(balls, own, season_drag, backspin, sidespin, own["park"].to_numpy(object))

    moved = balls if conditions.park is None else balls.assign(home_team=conditions.park)
    air = own.copy() if conditions.park is None else weather.air(moved)
    if conditions.temperature is not None:
        air["temperature"] = float(conditions.temperature)
    if conditions.wind_speed is not None:
        wx, wy = weather.wind_vector(np.full(len(balls), conditions.wind_direction, object),
                                     np.full(len(balls), float(conditions.wind_speed)))
        closed = air["roof_closed"].to_numpy(bool)
        air["wind_x"] = np.where(closed, 0.0, wx)
        air["wind_y"] = np.where(closed, 0.0, wy)
    drag = (season_drag if conditions.drag_scale is None
            else np.full(len(balls), float(conditions.drag_scale)))
    distance, x, y, call = _fly(balls, air, drag, backspin, sidespin,
                                air["park"].to_numpy(object))

    out = pd.DataFrame({c: balls[c] for c in ("game_pk", "at_bat_number", "pitch_number",
                                              "game_date", "home_team", "batter", "events",
                                              "bb_type", "launch_speed", "launch_angle",
                                              "spray_angle", "hit_distance_sc")})
    out["spray_angle"] = landing
    at = cast(int, out.columns.get_loc("spray_angle"))  # a unique column: its position
    out.insert(at + 1, "launch_spray_angle", spray)
    out["backspin"], out["sidespin"] = backspin, sidespin
    out["park"] = air["park"].to_numpy(object)
    out["temperature"] = air["temperature"].to_numpy(float)
    out["drag_scale"] = drag
    out["predicted_distance"], out["landing_x"], out["landing_y"] = distance, x, y
    out["fence_distance"] = call["fence_distance"].to_numpy(float)
    out["fence_height"] = call["fence_height"].to_numpy(float)
    out["home_run"] = call["home_run"].array
    out["home_run_probability"] = call["home_run_probability"].to_numpy(float)
    out["actual_park"] = own["park"].to_numpy(object)
    out["actual_temperature"] = own["temperature"].to_numpy(float)
    out["actual_distance"] = actual[0]
    out["actual_home_run"] = actual[3]["home_run"].array
    out["actual_home_run_probability"] = actual[3]["home_run_probability"].to_numpy(float)
    out["change"] = distance - actual[0]
    out.attrs["units"] = dict(OUTPUT_UNITS)
    out.attrs["conditions"] = dataclasses.asdict(conditions)
    return out


def replay_summary(out: pd.DataFrame) -> dict[str, Any]:
    """The replay's headline numbers: the median change of the fly balls and home runs of
    20-50 deg, their median carry replayed and as it was, and the home runs gained and
    lost (calls against the fences, replayed against as it was)."""
    angle = out["launch_angle"].to_numpy(float)
    kind = out["bb_type"].astype("string").fillna("")
    events = out["events"].astype("string").fillna("")
    window = ((angle >= 20) & (angle <= 50)
              & ((kind == "fly_ball") | (events == "home_run")).to_numpy(bool))
    change = out["change"].to_numpy(float)[window]
    change = change[np.isfinite(change)]
    replayed = out["home_run"].fillna(False).to_numpy(bool)
    before = out["actual_home_run"].fillna(False).to_numpy(bool)

    def median(values: NDArray[np.float64]) -> float:
        values = values[np.isfinite(values)]
        return float(np.median(values)) if values.size else math.nan

    return {"balls": len(out), "fly_balls_20_to_50_deg": int(window.sum()),
            "median_change_ft": median(change),
            "median_distance_ft": median(out["predicted_distance"].to_numpy(float)[window]),
            "median_actual_distance_ft": median(out["actual_distance"].to_numpy(float)[window]),
            "home_runs": int(replayed.sum()), "actual_home_runs": int(before.sum()),
            "expected_home_runs": float(np.nansum(out["home_run_probability"])),
            "actual_expected_home_runs": float(np.nansum(
                out["actual_home_run_probability"])),
            "home_runs_gained": int((replayed & ~before).sum()),
            "home_runs_lost": int((before & ~replayed).sum()),
            "measured_home_runs": int((events == "home_run").sum()),
            "unknown_fence_height": int(out["home_run"].isna().sum())}
