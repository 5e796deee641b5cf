"""``mcbat reproduce statcast``: the flight model's predicted distances against measured
Statcast distances.

For the fly balls, line drives and home runs of a Statcast file (by default the real
samples shipped in ``data/``: the 2,507 pitches of the eight games of 2020-09-03 and 438
pitches of Yu Darvish's five starts of July 2019), each ball is flown from its measured
launch (``launch_speed``, ``launch_angle``, ``spray_angle``) in the calculator's standard
weather (70 degF, 29.92 inHg, 50 %) at its park's elevation, with the spin of each spin
model, by each flight (``nathan``: the published model; a calibrated preset), and compared
with
``hit_distance_sc`` at the point the measurement refers to
(:mod:`~mcbat.papers.statcast.compare`). Writes, under one results directory::

    DIR/balls.parquet    one row per ball, spin model and flight: the launch, the
                         measurement, the spin, predicted_distance, residual
    DIR/summary.json     median, mean and rms of predicted minus measured, overall, per
                         10-degree launch-angle bin, per comparison class; per spin model
                         and flight
    DIR/figures/         predicted_vs_measured.png, residual_vs_launch_angle.png

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

from mcbat.bodies import BALL_PRESETS
from mcbat.dataset import storage
from mcbat.papers.outputs import ResultsDirectory
from mcbat.papers.statcast.compare import (
    CATCH_HEIGHT_FT,
    COMPARED,
    launch_angle_bins,
    residual_stats,
    select_balls,
)
from mcbat.papers.statcast.spin import nathan_average_spin
from mcbat.runner.plan import set_threads
from mcbat.statcast import read
from mcbat.study.flight import FLIGHT_PRESETS, FlightSettings, fly_launches
from mcbat.study.units import UNITS

__all__ = ["DEFAULT_DATA", "FLIGHTS", "SPIN_MODELS", "compare_file", "reproduce",
           "summarise"]

_FT, _MPH, _DEG, _RPM = (UNITS["length"]["ft"], UNITS["speed"]["mph"], UNITS["angle"]["deg"],
                          UNITS["spin"]["rpm"])
#: The shipped samples (resources of the ``mcbat.data`` package; ``data/README.md``).
DEFAULT_DATA = ("statcast_2020-09-03.csv", "statcast_2019_darvish.csv")
#: The ball every comparison flies: the project's (``mcbat flight``'s and studies').
BALL = BALL_PRESETS["baseball"]
#: Flights compared: name -> settings (at the calculator's standard weather).
FLIGHTS = {"nathan": FlightSettings(),
           **{name: FlightSettings(preset=name, model=p["model"],
                                   drag_scale=p["drag_scale"]["value"],
                                   lift_scale=p["lift_scale"]["value"])
              for name, p in FLIGHT_PRESETS.items()}}


def _nathan_spin(balls):
    return nathan_average_spin(balls["launch_angle"], balls["spray_angle"],
                               balls["handedness"])


def _inferred_spin(balls):
    """The spin of the contact that reproduces each ball's launch with its measured pitch
    through the game model (:func:`mcbat.inference.infer_spin`, its default assumptions);
    NaN where the inference did not converge."""
    from mcbat.inference import infer_spin

    out = infer_spin(balls)
    ok = (out["inference_status"] == "converged").to_numpy(bool)
    return (np.where(ok, out["backspin"].to_numpy(float), np.nan),
            np.where(ok, out["sidespin"].to_numpy(float), np.nan))


#: Spin models: name -> function of the balls' frame giving (backspin, sidespin) in rpm
#: (NaN: no spin for that ball, which is then not compared).
SPIN_MODELS = {"nathan": _nathan_spin, "inferred": _inferred_spin}

UNITS = {"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
         "hit_distance_sc": "ft", "elevation": "ft", "compare_height": "ft",
         "backspin": "rpm", "sidespin": "rpm", "predicted_distance": "ft", "residual": "ft"}


def read_statcast(path=None) -> tuple[pd.DataFrame, str]:
    """The tidy table (:func:`mcbat.statcast.read`) of a Statcast file, or of the shipped
    samples when ``path`` is None, and a description of the source."""
    if path is not None:
        return read(path), str(path)
    tables = []
    for name in DEFAULT_DATA:
        with resources.as_file(resources.files("mcbat.data") / name) as file:
            tables.append(read(file))
    table = pd.concat(tables, ignore_index=True)
    return table, " + ".join(f"data/{name}" for name in DEFAULT_DATA) + " (shipped)"


def compare_file(table: pd.DataFrame, source=None) -> pd.DataFrame:
    """Every selected ball flown by every spin model and flight: the long table written to
    ``balls.parquet`` (module docstring)."""
    balls = select_balls(table, source)
    balls.insert(0, "ball", np.arange(len(balls)))
    flown = balls["comparison"].isin(COMPARED).to_numpy(bool)
    parts = []
    for spin_name, spin in SPIN_MODELS.items():
        backspin, sidespin = (np.asarray(x, float) for x in spin(balls))
        for flight_name, settings in FLIGHTS.items():
            out, status = fly_launches(
                settings, BALL.mass, BALL.radius, balls["launch_speed"].to_numpy() * _MPH,
                balls["launch_angle"].to_numpy() * _DEG,
                balls["spray_angle"].to_numpy() * _DEG, backspin * _RPM, sidespin * _RPM,
                elevation=balls["elevation"].to_numpy() * _FT,
                landing_height=balls["compare_height"].to_numpy() * _FT)
            spun = np.isfinite(backspin) & np.isfinite(sidespin)
            predicted = np.where((status == 0) & flown & spun, out["hit_distance"] / _FT,
                                 np.nan)
            part = balls.copy()
            part["spin_model"] = spin_name
            part["flight"] = flight_name
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
        window = compared[(compared["launch_angle"] >= 20) & (compared["launch_angle"] <= 50)
                          & ((compared["bb_type"] == "fly_ball")
                             | (compared["comparison"] == "home_run"))]
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
            "not_risen_to_catch_height": int(((part["flight_status"] == 3)
                                              & part["comparison"].isin(COMPARED)).sum()),
            "without_spin": int((~np.isfinite(part["backspin"])
                                 & part["comparison"].isin(COMPARED)).sum()),
        }
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


def reproduce(out="results", *, data=None, threads=None, echo=print, overwrite=False) -> dict:
    """Compare, write ``balls.parquet``, ``summary.json`` and the figures under ``out``
    (module docstring); returns the paths written. ``data``: a Statcast file (default the
    shipped sample)."""
    from mcbat.papers.statcast import figures

    t0 = time.perf_counter()
    set_threads(threads)
    table, source = read_statcast(data)
    results = ResultsDirectory(Path(out), "statcast",
                               ("balls.parquet", "figures", "summary.json"),
                               overwrite=overwrite)
    long = compare_file(table, source)
    residuals = summarise(long)
    first = long[(long["spin_model"] == long["spin_model"].cat.categories[0])
                 & (long["flight"] == "nathan")]
    summary = {
        "data": source, "rows_read": len(table), "balls": int(len(first)),
        "by_comparison": {str(k): int(v) for k, v in
                          first["comparison"].value_counts(sort=False).items()},
        "catch_height_ft": CATCH_HEIGHT_FT,
        "ball": {"preset": BALL.preset, "mass_kg": BALL.mass, "radius_m": BALL.radius},
        "weather": "70 degF, 29.92 inHg (sea level), 50 % RH, at each park's elevation",
        "flights": {name: {**s.config(), "elevation_m": "each ball's park (elevation)",
                           "landing_height_m": "each ball's compare_height"}
                    for name, s in FLIGHTS.items()},
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
                 figures.residual_vs_launch_angle(fig_dir, long)]
        summary_path = results.write_text(
            "summary.json", json.dumps(_finite(summary), indent=2, allow_nan=False) + "\n")
    echo(f"{summary['balls']} balls of {source} ({len(table)} rows read)")
    echo(text)
    echo("")
    echo(f"results in {root}/ ({time.perf_counter() - t0:.1f} s):")
    echo(f"  balls    {root / 'balls.parquet'}")
    echo(f"  summary  {summary_path}")
    for path in paths:
        echo(f"  figure   {path}")
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
