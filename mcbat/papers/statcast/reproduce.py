"""``mcbat reproduce statcast``: the flight model's predicted distances against measured
Statcast distances.

For the fly balls, line drives and home runs of a Statcast file (by default the real
samples shipped in ``data/``: the 2,507 pitches of the eight games of 2020-09-03 and 438
pitches of Yu Darvish's five starts of July 2019), each ball is flown from its measured
launch (``launch_speed``, ``launch_angle``, ``spray_angle``) with the regulation ball, with
the spin of each spin model, by each flight, and compared with ``hit_distance_sc`` at the
point the measurement refers to (``mcbat.papers.statcast.compare``). The flights:

``season`` (the default)
    Nathan's model with its season's fitted drag and lift
    (``mcbat.study.flight.flight_seasons``; the published model for a season the table
    lacks), each ball in its own park and air (``mcbat.statcast.weather.air``: the
    game's weather when a weather table is given, else the park's climate normal for the
    month; indoor air and no wind under a closed roof). A weather table's recorded wind
    is felt at the season table's ``wind_scale`` (0.05: the recorded wind at first pitch
    barely predicts the carry; ``docs/flight.md``).
``published``
    Nathan's published model in the same air.
``standard_air``
    Nathan's published model in the calculator's standard weather (70 degF, 29.92 inHg,
    50 %, no wind) at the park's elevation.

Writes, under one results directory::

    DIR/balls.parquet    one row per ball, spin model and flight: the launch, the
                         measurement, the ball's air, the spin, predicted_distance,
                         residual, and ``default`` (True for the default flight and
                         spin model: ``season`` and ``nathan``)
    DIR/summary.json     median, mean and rms of predicted minus measured, overall, per
                         10-degree launch-angle bin, per comparison class, and for the fly
                         balls and home runs of 20-50 deg by season, month and game
                         temperature; per spin model and flight
    DIR/figures/         predicted_vs_measured.png, residual_vs_launch_angle.png,
                         residual_by_season_month_temperature.png

Deterministic: the same files at every run.
"""

from __future__ import annotations

import json
import math
import time
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL
from mcbat.core.units import M_PER_FT, M_S_PER_MPH, RAD_PER_DEG, RAD_S_PER_RPM
from mcbat.dataset import storage
from mcbat.papers.outputs import ResultsDirectory, echo_results
from mcbat.papers.statcast.compare import (
    CATCH_HEIGHT_FT,
    COMPARED,
    eligible_window,
    launch_angle_bins,
    residual_stats,
    select_balls,
)
from mcbat.runner.plan import set_threads
from mcbat.solving import FlightStatus
from mcbat.statcast import read, weather
from mcbat.statcast.launch import launch_spray
from mcbat.statcast.spin import nathan_average_spin
from mcbat.study.flight import FlightSettings, fly_launches, season_scales, season_wind_scale

__all__ = ["AIR_UNITS", "DEFAULT_DATA", "DEFAULT_FLIGHT", "DEFAULT_SPIN", "FLIGHTS",
           "SPIN_MODELS", "air_per_ball", "balls_in_their_air", "compare_file", "reproduce",
           "summarise"]

#: The shipped samples (resources of the ``mcbat.data`` package; ``data/README.md``).
DEFAULT_DATA = ("statcast_2020-09-03.csv", "statcast_2019_darvish.csv")
#: The ball every comparison flies: the regulation baseball of games and flights.
BALL = BALL_PRESETS[DEFAULT_BALL]
#: Flights compared (module docstring): name -> (scales, air). ``scales``: "season" (each
#: ball's season, ``mcbat.study.flight.season_scales``) or "published" (1, 1);
#: ``air``: "game" (``mcbat.statcast.weather.air``) or "standard".
FLIGHTS = {"season": ("season", "game"), "published": ("published", "game"),
           "standard_air": ("published", "standard")}
#: The default flight and spin model (``balls.parquet``'s ``default`` column).
DEFAULT_FLIGHT, DEFAULT_SPIN = "season", "nathan"
#: The flights' shared settings: Nathan's model, the calculator's launch point and decay.
SETTINGS = FlightSettings()


def _nathan_spin(balls):
    """Nathan's average spin for each ball's launch direction."""
    return nathan_average_spin(balls["launch_angle"], balls["launch_spray_angle"],
                               balls["handedness"])


def _inferred_spin(balls):
    """The spin of the contact that reproduces each ball's launch with its measured pitch
    through the game model (``mcbat.inference.infer_spin``, its default assumptions);
    NaN where the inference did not converge."""
    from mcbat.inference import infer_spin

    out = infer_spin(balls)
    ok = (out["inference_status"] == "converged").to_numpy(bool)
    return (np.where(ok, out["backspin"].to_numpy(float), np.nan),
            np.where(ok, out["sidespin"].to_numpy(float), np.nan))


#: Spin models: name -> function of the balls' frame giving (backspin, sidespin) in rpm
#: (NaN: no spin for that ball, which is then not compared).
SPIN_MODELS = {"nathan": _nathan_spin, "inferred": _inferred_spin}
#: The launch direction each spin model flies a ball from: Nathan's spin from the direction
#: that comes down along the measured spray angle; the inferred spin's contact reproduces
#: the measured spray angle as the launch direction.
SPRAY_COLUMNS = {"nathan": "launch_spray_angle", "inferred": "spray_angle"}

#: Units of the air columns of ``balls.parquet`` (Statcast-style: degF, inHg, %, m/s).
AIR_UNITS = {"temperature": "degF", "pressure": "inHg", "relative_humidity": "%",
             "wind_x": "m/s", "wind_y": "m/s"}
UNITS = {"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
         "launch_spray_angle": "deg",
         "hit_distance_sc": "ft", "elevation": "ft", "compare_height": "ft",
         "backspin": "rpm", "sidespin": "rpm", "predicted_distance": "ft", "residual": "ft",
         "drag_scale": "1", "lift_scale": "1", **AIR_UNITS}


def read_statcast(path=None) -> tuple[pd.DataFrame, str]:
    """The tidy table (``mcbat.statcast.read``) of a Statcast file, or of the shipped
    samples when ``path`` is None, and a description of the source."""
    if path is not None:
        return read(path), str(path)
    tables = []
    for name in DEFAULT_DATA:
        with resources.as_file(resources.files("mcbat.data") / name) as file:
            tables.append(read(file))
    table = pd.concat(tables, ignore_index=True)
    return table, " + ".join(f"data/{name}" for name in DEFAULT_DATA) + " (shipped)"


def air_per_ball(air: pd.DataFrame, wind_scale: float = 1.0) -> dict:
    """The per-ball flight settings (SI, ``mcbat.study.flight.PER_BALL``) of an
    ``mcbat.statcast.weather.air`` frame, its wind times ``wind_scale``."""
    return {"temperature": (air["temperature"].to_numpy(float) - 32.0) * 5.0 / 9.0 + 273.15,
            "pressure": air["pressure"].to_numpy(float) * 3386.389,
            "relative_humidity": air["relative_humidity"].to_numpy(float),
            "elevation": air["elevation"].to_numpy(float) * M_PER_FT,
            "wind_x": air["wind_x"].to_numpy(float) * wind_scale,
            "wind_y": air["wind_y"].to_numpy(float) * wind_scale}


def balls_in_their_air(table: pd.DataFrame, source=None, weather_table=None) -> pd.DataFrame:
    """The compared balls of ``table`` (``mcbat.papers.statcast.compare.select_balls``)
    with the air each was hit in (``mcbat.statcast.weather.air``: ``elevation``,
    ``temperature``, ``pressure``, ``relative_humidity``, ``wind_x``, ``wind_y``,
    ``roof_closed``, ``air_source``, ``wind_source``), from ``weather_table`` or the parks'
    climate, and ``launch_spray_angle`` (deg): the direction each left the bat in, whose
    flight with Nathan's spin (the published model in that air, without a recorded wind)
    comes down along the measured ``spray_angle``
    (:func:`mcbat.statcast.launch.launch_spray`)."""
    balls = select_balls(table, source)
    air = weather.air(balls, weather_table).reset_index(drop=True)
    for column in ("elevation", "temperature", "pressure", "relative_humidity", "wind_x",
                   "wind_y", "roof_closed", "air_source", "wind_source"):
        balls[column] = air[column].to_numpy()
    # The launch direction with the published model in the game's air, its recorded wind
    # left out: so that it does not move with a refit of the season table.
    balls["launch_spray_angle"] = launch_spray(
        balls["launch_speed"], balls["launch_angle"], balls["spray_angle"],
        balls["handedness"], per_ball=air_per_ball(balls, 0.0), settings=SETTINGS,
        ball=BALL)[0]
    return balls


def compare_file(table: pd.DataFrame, source=None, *, weather_table=None,
                 spin_models=None) -> pd.DataFrame:
    """Every selected ball flown by every spin model and flight: the long table written to
    ``balls.parquet`` (module docstring). ``weather_table``: a per-game weather table
    (``mcbat.statcast.weather.read_weather``), else each park's climate normals;
    ``spin_models``: names of ``SPIN_MODELS`` (default all)."""
    balls = balls_in_their_air(table, source, weather_table)
    balls.insert(0, "ball", np.arange(len(balls)))
    drag, lift, _ = season_scales(balls["game_year"])
    game_air = air_per_ball(balls, season_wind_scale())
    standard_air = {"elevation": game_air["elevation"]}
    flown = balls["comparison"].isin(COMPARED).to_numpy(bool)
    parts = []
    for spin_name in (SPIN_MODELS if spin_models is None else spin_models):
        backspin, sidespin = (np.asarray(x, float) for x in SPIN_MODELS[spin_name](balls))
        spun = np.isfinite(backspin) & np.isfinite(sidespin)
        for flight_name, (scales, air_kind) in FLIGHTS.items():
            per_ball = dict(game_air if air_kind == "game" else standard_air)
            drag_scale = drag if scales == "season" else np.ones(len(balls))
            lift_scale = lift if scales == "season" else np.ones(len(balls))
            per_ball.update(drag_scale=drag_scale, lift_scale=lift_scale,
                            landing_height=balls["compare_height"].to_numpy() * M_PER_FT)
            out, status = fly_launches(
                SETTINGS, BALL.mass, BALL.radius, balls["launch_speed"].to_numpy() * M_S_PER_MPH,
                balls["launch_angle"].to_numpy() * RAD_PER_DEG,
                balls[SPRAY_COLUMNS[spin_name]].to_numpy() * RAD_PER_DEG,
                np.where(spun, backspin, 0.0) * RAD_S_PER_RPM,
                np.where(spun, sidespin, 0.0) * RAD_S_PER_RPM, per_ball=per_ball)
            landed = status == FlightStatus.OK
            predicted = np.where(landed & flown & spun, out["hit_distance"] / M_PER_FT, np.nan)
            part = balls.copy()
            part["spin_model"] = spin_name
            part["flight"] = flight_name
            part["default"] = spin_name == DEFAULT_SPIN and flight_name == DEFAULT_FLIGHT
            part["drag_scale"] = drag_scale
            part["lift_scale"] = lift_scale
            if air_kind == "standard":
                part["temperature"], part["pressure"] = 70.0, 29.92
                part["relative_humidity"], part["wind_x"], part["wind_y"] = 50.0, 0.0, 0.0
                part["air_source"] = "standard"
            part["backspin"] = backspin
            part["sidespin"] = sidespin
            part["predicted_distance"] = predicted
            part["residual"] = predicted - balls["hit_distance_sc"].to_numpy()
            part["flight_status"] = status
            parts.append(part)
    long = pd.concat(parts, ignore_index=True)
    long["spin_model"] = pd.Categorical(long["spin_model"], categories=list(SPIN_MODELS))
    long["flight"] = pd.Categorical(long["flight"], categories=list(FLIGHTS))
    long.attrs["units"] = {c: UNITS[c] for c in long.columns if c in UNITS}
    return long


def _bin_label(left):
    return f"{left:.0f} to {left + 10:.0f}"


def summarise(long: pd.DataFrame) -> dict:
    """Residual statistics per spin model and flight (``summary.json``'s ``residuals``)."""
    out = {}
    for (spin, flight), part in long.groupby(["spin_model", "flight"], observed=True,
                                             sort=False):
        compared = part[part["comparison"].isin(COMPARED)]
        fit_like = compared[compared["comparison"].isin(("catch", "home_run"))]
        bins = launch_angle_bins(compared["launch_angle"])
        by_bin = {_bin_label(b): residual_stats(compared["residual"][bins == b])
                  for b in np.unique(bins)}
        fb_bins = launch_angle_bins(fit_like["launch_angle"])
        by_bin_fit = {_bin_label(b): residual_stats(fit_like["residual"][fb_bins == b])
                      for b in np.unique(fb_bins)}
        window = part[eligible_window(part)]
        out.setdefault(str(spin), {})[str(flight)] = {
            "all": {"overall": residual_stats(compared["residual"]),
                    "by_launch_angle": by_bin},
            "catch_and_home_run": {"overall": residual_stats(fit_like["residual"]),
                                   "by_launch_angle": by_bin_fit},
            "by_comparison": {c: residual_stats(compared["residual"][
                compared["comparison"] == c]) for c in COMPARED},
            "home_run": residual_stats(compared["residual"][
                compared["comparison"] == "home_run"]),
            "fly_ball_and_home_run_20_to_50_deg": residual_stats(window["residual"]),
            "fly_ball_and_home_run_20_to_50_deg_by": breakdowns(window),
            "eligible_20_to_50_deg": int(len(window)),
            "compared_20_to_50_deg": int(np.isfinite(window["residual"]).sum()),
            "not_risen_to_catch_height": int(((part["flight_status"] == 3)
                                              & part["comparison"].isin(COMPARED)).sum()),
            "without_spin": int((~np.isfinite(part["backspin"])
                                 & part["comparison"].isin(COMPARED)).sum()),
        }
    return out


#: Game temperature bin edges of the breakdowns (degF).
TEMPERATURE_EDGES = (50.0, 60.0, 70.0, 80.0, 90.0)
TEMPERATURE_LABELS = (f"below {TEMPERATURE_EDGES[0]:.0f}",
                      *(f"{lo:.0f} to {hi:.0f}" for lo, hi in
                        zip(TEMPERATURE_EDGES, TEMPERATURE_EDGES[1:])),
                      f"{TEMPERATURE_EDGES[-1]:.0f} and above")


def breakdowns(window: pd.DataFrame) -> dict:
    """Residual statistics of ``window`` (rows of the long table) by season
    (``game_year``), calendar month (of ``game_date``) and game temperature (degF, the
    air each ball was flown in)."""
    dates = pd.to_datetime(window["game_date"], errors="coerce")
    residual = window["residual"].to_numpy(float)
    out = {"season": {}, "month": {}, "temperature": {}}
    for season in sorted(pd.unique(window["game_year"].dropna())):
        out["season"][str(int(season))] = residual_stats(
            residual[(window["game_year"] == season).to_numpy(bool)])
    months = dates.dt.month.to_numpy(float)
    for month in sorted(np.unique(months[np.isfinite(months)])):
        out["month"][f"{int(month):02d}"] = residual_stats(residual[months == month])
    temperature = window["temperature"].to_numpy(float)
    index = np.searchsorted(TEMPERATURE_EDGES, temperature, side="right")
    for i, label in enumerate(TEMPERATURE_LABELS):
        out["temperature"][label + " degF"] = residual_stats(
            residual[(index == i) & np.isfinite(temperature)])
    return out


def format_table(residuals: dict) -> str:
    """The printed residual table: per spin model, launch-angle bins by flight."""
    lines = []
    for spin, flights in residuals.items():
        names = list(flights)
        lines.append(f"spin model {spin!r}: predicted minus measured distance (ft), "
                     "median / mean / rms (n)")
        head = f"{'launch angle':<14}" + "".join(f"{name:>28}" for name in names)
        lines.append(head)
        bins = list(next(iter(flights.values()))["all"]["by_launch_angle"])

        def cell(s):
            if not s["n"]:
                return f"{'-':>28}"
            return f"{s['median']:>8.1f} {s['mean']:>6.1f} {s['rms']:>6.1f} ({s['n']:>3})"

        for b in bins:
            lines.append(f"{b + ' deg':<14}" + "".join(
                cell(flights[n]["all"]["by_launch_angle"][b]) for n in names))
        rows = (("all", lambda f: f["all"]["overall"]),
                ("catches", lambda f: f["by_comparison"]["catch"]),
                ("home runs", lambda f: f["home_run"]),
                ("hits in play", lambda f: f["by_comparison"]["hit"]),
                ("FB+HR 20-50", lambda f: f["fly_ball_and_home_run_20_to_50_deg"]))
        for label, get in rows:
            lines.append(f"{label:<14}" + "".join(cell(get(flights[n])) for n in names))
        lines.append("")
    return "\n".join(lines).rstrip()


def _write_parquet(long: pd.DataFrame, path: Path) -> None:
    table = pa.Table.from_pandas(long, preserve_index=False)
    meta = dict(table.schema.metadata or {})
    meta[b"mcbat"] = json.dumps({"units": long.attrs["units"]}).encode()
    table = table.replace_schema_metadata(meta)
    storage.write_atomic(path, lambda fs, tmp: pq.write_table(table, tmp, filesystem=fs))


def reproduce(out="results", *, data=None, weather_path=None, threads=None, echo=print,
              overwrite=False) -> dict:
    """Compare, write ``balls.parquet``, ``summary.json`` and the figures under ``out``
    (module docstring); returns the paths written. ``data``: a Statcast file (default the
    shipped sample); ``weather_path``: a per-game weather table
    (``mcbat.statcast.weather.read_weather``; default: each park's climate)."""
    from mcbat.papers.statcast import figures

    t0 = time.perf_counter()
    set_threads(threads)
    table, source = read_statcast(data)
    results = ResultsDirectory(Path(out), "statcast",
                               ("balls.parquet", "figures", "summary.json"),
                               overwrite=overwrite)
    weather_table = None if weather_path is None else weather.read_weather(weather_path)
    long = compare_file(table, source, weather_table=weather_table)
    residuals = summarise(long)
    first = long[long["default"]]
    summary = {
        "data": source, "rows_read": len(table), "balls": int(len(first)),
        "by_comparison": {str(k): int(v) for k, v in
                          first["comparison"].value_counts(sort=False).items()},
        "catch_height_ft": CATCH_HEIGHT_FT,
        "ball": {"preset": BALL.preset, "mass_kg": BALL.mass, "radius_m": BALL.radius},
        "weather": (str(weather_path) if weather_path is not None else
                    "none given: each park's climate normal for the month"),
        "air_sources": {str(k): int(v) for k, v in
                        first["air_source"].value_counts(sort=False).items()},
        "flights": {name: {"scales": scales, "air": air_kind}
                    for name, (scales, air_kind) in FLIGHTS.items()},
        "default": {"flight": DEFAULT_FLIGHT, "spin_model": DEFAULT_SPIN},
        "settings": SETTINGS.config(),
        "spin_models": list(SPIN_MODELS),
        "residual": "predicted_distance - hit_distance_sc",
        "residuals": residuals,
        "units": {"residuals": "ft", "catch_height_ft": "ft"},
    }
    text = format_table(residuals)
    with results.writing():
        root = results.root
        _write_parquet(long, root / "balls.parquet")
        fig_dir = results.directory("figures")
        paths = [figures.predicted_vs_measured(fig_dir, long),
                 figures.residual_vs_launch_angle(fig_dir, long),
                 figures.residual_breakdowns(fig_dir, long[long["default"]])]
        summary_path = results.write_text(
            "summary.json", json.dumps(_finite(summary), indent=2, allow_nan=False) + "\n")
    echo(f"{summary['balls']} balls of {source} ({len(table)} rows read)")
    echo(text)
    echo("")
    echo_results(echo, root, time.perf_counter() - t0,
                 [("balls", root / "balls.parquet"), ("summary", summary_path)], paths, 9)
    return {"balls": root / "balls.parquet", "summary": summary_path, "figures": paths,
            "residuals": residuals}


def _finite(obj):
    """Non-finite floats as None (strict JSON)."""
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj
