"""Calibrate the flight model's drag and lift to measured distances.

The fit (``mcbat.stats.fit.estimate.fit`` with ``mcbat.stats.models.flight.FlightModel``)
scales the spin-free drag ``C_D0`` and the lift ``C_L`` of Nathan's model so that the
predicted distances of the balls whose measured point is known best (outfield catches at
the catch height, home runs projected to the ground; ``mcbat.papers.statcast.compare``)
match ``hit_distance_sc``. Hits in play are left out of the fit: a ball that struck a wall
is measured short of its carry, and nothing in the data says which did. Only the fly balls
and home runs launched at 20-50 deg are fitted
(``mcbat.papers.statcast.compare.eligible_window``): their carry is what the drag
decides, while a line drive caught low depends as much on the guessed catch height.

The per-ball scatter ``sigma`` (ft) is not a measurement error: it is what the launch
numbers do not determine, each ball's own spin about the average spin model, the day's
weather and wind, the catch height, the tracking. It is taken from the data: a first fit
with the robust spread of the uncalibrated residuals (1.4826 x their median absolute
deviation), then ``sigma`` = the rms of the residuals about that fit with ``n - 2``
degrees of freedom, and the fit again with it for the profile intervals. With one
``sigma`` for every ball the best fit does not depend on it (the same least squares), and
the intervals scale with it. The chi2 of the second fit is then ``n - 2`` by construction:
the check of the fit is the residuals by launch angle (the figures of ``mcbat reproduce
statcast``), not its chi2.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd

from mcbat.errors import InputError
from mcbat.papers.statcast.compare import eligible_window, residual_stats
from mcbat.stats.fit.estimate import fit
from mcbat.stats.models.flight import AIR_COLUMNS, FLIGHT_TABLE_COLUMNS, FlightFitSetup
from mcbat.study.flight import FlightSettings

__all__ = ["DISTANCE_SLOPE", "FIT_CLASSES", "FREE", "LAUNCH_SPEED_MEDIAN",
           "MIN_DISTANCE_CORRELATION", "FlightCalibration", "calibrate",
           "check_distances_follow_launch", "check_launch_speeds", "fit_scales",
           "flight_table", "predict"]

#: Comparison classes the fit uses.
FIT_CLASSES = ("catch", "home_run")
#: The calibrated parameters.
FREE = ("drag_scale", "lift_scale")
#: Fewest balls a calibration takes.
MIN_BALLS = 10


@dataclasses.dataclass
class FlightCalibration:
    """A fitted calibration: the ``mcbat.stats.fit.estimate.FitResult``, the per-ball scatter
    ``sigma`` (ft) it used, and the number of balls."""

    result: object
    sigma: float
    balls: int
    spin_model: str
    source: str | None = None
    holdout: dict | None = None
    """In-sample and held-out residuals (``hold_out``), when computed."""

    def to_dict(self) -> dict:
        """JSON-ready: the fit (``FitResult.to_dict``), ``sigma_ft``, ``balls``, the
        spin model, the data and the hold-out check."""
        return {**self.result.to_dict(), "sigma_ft": self.sigma, "balls": self.balls,
                "spin_model": self.spin_model, "fit_classes": list(FIT_CLASSES),
                "data": self.source, "holdout": self.holdout}

    def lines(self) -> list[str]:
        """As printed by ``mcbat fit --flight``."""
        r = self.result
        out = [*r.lines(),
               f"  per-ball scatter sigma = {self.sigma:.1f} ft (rms of the residuals, "
               f"{self.balls} - {len(r.params)} degrees of freedom)",
               f"  chi2 / dof = {r.chi2:.1f} / {r.dof} (1 by construction of sigma)"]
        h = self.holdout
        if h is None:
            return out
        if h.get("out_of_sample") is None:
            return [*out, f"  held out: {h['note']}"]

        def cell(s):
            return f"median {s['median']:+.1f} ft, rms {s['rms']:.1f} ft ({s['n']} balls)"

        return [*out, "  predicted minus measured, 20-50 deg catches and home runs:",
                f"    in sample (this fit):             {cell(h['in_sample'])}",
                f"    held out (fit to the other games): {cell(h['out_of_sample'])}"]


def flight_table(balls: pd.DataFrame, backspin, sidespin, sigma) -> pd.DataFrame:
    """The measurement table of ``mcbat.stats.models.flight.FlightModel`` for
    ``balls`` (a ``mcbat.papers.statcast.compare.select_balls`` frame) flown with
    ``backspin``, ``sidespin`` (rpm), with the scatter ``sigma`` (ft) per ball."""
    table = pd.DataFrame({c: balls[c].to_numpy(float) for c in
                          ("launch_speed", "launch_angle", "spray_angle", "elevation",
                           "hit_distance_sc")})
    if "launch_spray_angle" in balls.columns:  # the direction it left the bat in
        table["spray_angle"] = balls["launch_spray_angle"].to_numpy(float)
    table["backspin"] = np.asarray(backspin, float)
    table["sidespin"] = np.asarray(sidespin, float)
    table["landing_height"] = balls["compare_height"].to_numpy(float)
    for column in AIR_COLUMNS:
        if column in balls.columns:
            table[column] = balls[column].to_numpy(float)
    table["hit_distance_sc_err"] = np.broadcast_to(np.asarray(sigma, float), len(table))
    return table[[c for c in (*FLIGHT_TABLE_COLUMNS, "hit_distance_sc_err")
                  if c in table.columns]]


def check_free(free) -> tuple:
    """``free`` (a comma-separated string or names; None: both scales) as a tuple of
    distinct names of ``FREE``, or ``InputError``."""
    if free is None:
        return FREE
    names = [p.strip() for p in free.split(",")] if isinstance(free, str) else list(free)
    unknown = [p for p in names if p not in FREE]
    if unknown or not names or len(set(names)) != len(names):
        raise InputError("free", f"the flight fit takes {' and/or '.join(FREE)} (distinct), "
                         f"got {free!r}")
    return tuple(p for p in FREE if p in names)


def calibrate_file(path=None, *, spin_model="nathan", free=None, intervals="profile",
                   weather_path=None) -> FlightCalibration:
    """Read a Statcast file (None: the shipped samples), select its balls, give each its
    air (the games' weather from ``weather_path``, else each park's climate) and calibrate
    (``calibrate``) with the spin of ``spin_model``."""
    from mcbat.papers.statcast.reproduce import SPIN_MODELS, balls_in_their_air, read_statcast
    from mcbat.statcast.weather import read_weather

    free = check_free(free)
    if spin_model not in SPIN_MODELS:
        raise InputError("spin_model", f"must be one of {', '.join(SPIN_MODELS)}, got "
                         f"{spin_model!r}")
    table, source = read_statcast(path)
    balls = balls_in_their_air(table, source, None if weather_path is None
                               else read_weather(weather_path))
    backspin, sidespin = SPIN_MODELS[spin_model](balls)
    cal = calibrate(balls, backspin, sidespin, spin_model=spin_model, free=free,
                    intervals=intervals, source=source)
    cal.holdout = hold_out(balls, backspin, sidespin, cal, free=free)
    return cal


def hold_out(balls: pd.DataFrame, backspin, sidespin, cal: FlightCalibration, *,
             free=FREE) -> dict:
    """The fit judged on balls it did not see: the games of ``balls`` split in two halves
    (alternate ``game_pk``), each half's 20-50 deg catches and home runs predicted by the
    fit to the other half; beside them, the same balls predicted by ``cal`` (the fit to
    all: in sample). Returns ``{"in_sample", "out_of_sample"}`` residual statistics (ft),
    or ``{"out_of_sample": None, "note"}`` when a half has too few balls to fit."""
    backspin = np.asarray(backspin, float)
    sidespin = np.asarray(sidespin, float)
    use = eligible_window(balls) & balls["comparison"].isin(FIT_CLASSES).to_numpy(bool)
    setup = FlightFitSetup()
    table = flight_table(balls, backspin, sidespin, 1.0)
    games = np.unique(balls["game_pk"].to_numpy())
    half = balls["game_pk"].isin(set(games[1::2].tolist())).to_numpy(bool)
    in_sample = predict(setup, table, dict(cal.result.params)) - table[
        "hit_distance_sc"].to_numpy()
    held = np.full(len(balls), np.nan)
    for part in (half, ~half):
        rest = ~part
        if (use & rest).sum() < MIN_BALLS or (use & part).sum() == 0:
            return {"in_sample": residual_stats(in_sample[use]), "out_of_sample": None,
                    "note": f"too few games to hold half out ({len(games)} games, "
                            f"{int(use.sum())} balls)"}
        other = calibrate(balls[rest].reset_index(drop=True), backspin[rest], sidespin[rest],
                          free=free, intervals="curvature")
        held[part] = predict(setup, table[part].reset_index(drop=True),
                             dict(other.result.params)) - table.loc[
            part, "hit_distance_sc"].to_numpy()
    return {"in_sample": residual_stats(in_sample[use]),
            "out_of_sample": residual_stats(held[use]), "split": "alternate games"}


def calibrate(balls: pd.DataFrame, backspin, sidespin, *, spin_model="nathan",
              settings: FlightSettings | None = None, ball=None, free=FREE,
              intervals="profile", source=None) -> FlightCalibration:
    """Fit ``drag_scale`` and ``lift_scale`` to the catches and home runs of ``balls``
    flown with the given spin (module docstring).

    Parameters
    ----------
    balls : pandas.DataFrame
        ``mcbat.papers.statcast.compare.select_balls``.
    backspin, sidespin : array_like
        rpm, per ball.
    settings : FlightSettings, optional
        The flight (default: the published model at standard weather; the elevation is
        the balls').
    ball : mcbat.bodies.Ball, optional
        Default: the ``baseball`` preset.
    intervals : {"profile", "curvature"}
        As ``mcbat.stats.fit.estimate.fit``.

    Raises
    ------
    InputError
        Naming ``hit_distance_sc`` when fewer than ``MIN_BALLS`` balls qualify or the
        distances do not follow the launches (``check_distances_follow_launch``);
        naming ``launch_speed`` when the launch speeds are not in mph
        (``check_launch_speeds``).
    """
    use = eligible_window(balls) & balls["comparison"].isin(FIT_CLASSES).to_numpy(bool)
    check_launch_speeds(balls["launch_speed"].to_numpy(float)[use], source)
    settings = FlightSettings() if settings is None else settings
    setup = FlightFitSetup(settings=settings) if ball is None else FlightFitSetup(
        settings=settings, mass=ball.mass, radius=ball.radius)
    backspin = np.broadcast_to(np.asarray(backspin, float), use.shape)
    sidespin = np.broadcast_to(np.asarray(sidespin, float), use.shape)
    table = flight_table(balls, backspin, sidespin, 1.0)
    table.attrs["source"] = source
    # Balls that never rise to their catch height have no prediction (low line drives).
    model = predict(setup, table)
    use = use & np.isfinite(model)
    if use.sum() < MIN_BALLS:
        raise InputError("hit_distance_sc", f"{int(use.sum())} outfield catches and home runs "
                         f"with a prediction; a calibration needs at least {MIN_BALLS}",
                         source)
    table = table[use].reset_index(drop=True)
    table.attrs["source"] = source
    return fit_scales(table, setup, free=free, intervals=intervals, spin_model=spin_model,
                      source=source)


def fit_scales(table: pd.DataFrame, setup: FlightFitSetup | None = None, *,
               free=FREE, intervals="profile", spin_model="nathan",
               source=None) -> FlightCalibration:
    """Fit ``drag_scale`` and ``lift_scale`` to a ``flight_table`` whose every row
    has a prediction, with the per-ball scatter taken from the data (module docstring;
    the table's ``hit_distance_sc_err`` is replaced)."""
    table = table.copy()
    setup = FlightFitSetup() if setup is None else setup
    model = predict(setup, table)
    check_distances_follow_launch(table["hit_distance_sc"].to_numpy(float), model, source)
    residual = model - table["hit_distance_sc"].to_numpy()
    sigma0 = 1.4826 * float(np.median(np.abs(residual - np.median(residual))))
    table["hit_distance_sc_err"] = max(sigma0, 0.1)
    first = fit(setup, table, free, intervals="curvature")
    best = [first.params[p] for p in free]
    fitted = predict(setup, table, dict(zip(free, best)))
    n = len(table)
    sigma = math.sqrt(float(np.sum((fitted - table["hit_distance_sc"].to_numpy()) ** 2))
                      / (n - len(free)))
    table["hit_distance_sc_err"] = sigma
    result = fit(setup, table, free, start=best, intervals=intervals)
    return FlightCalibration(result=result, sigma=sigma, balls=n, spin_model=spin_model,
                             source=source)


#: The median launch speed (mph) of the fitted balls (fly balls launched at 20-50 deg and
#: home runs) lies in this range in every real export (90-100 mph): outside it the launch
#: speeds are in another unit (m/s: ~42, km/h: ~150).
LAUNCH_SPEED_MEDIAN = (70.0, 125.0)
#: Measured distances follow the model's uncalibrated predictions of the same launches
#: with a correlation of 0.95-0.98 and a slope of 0.92-1.07 on the real exports: a table
#: whose correlation is below this, or whose slope lies outside ``DISTANCE_SLOPE``,
#: does not hold distances of balls flown from those launches, and a fit of the scales to
#: it would be meaningless (the scatter model, one sigma about the flight, would not hold).
MIN_DISTANCE_CORRELATION = 0.5
DISTANCE_SLOPE = (0.5, 2.0)


def check_launch_speeds(launch_speed, source=None) -> None:
    """``InputError`` naming ``launch_speed`` when the fitted balls' median launch
    speed (mph) lies outside ``LAUNCH_SPEED_MEDIAN``."""
    values = np.asarray(launch_speed, float)
    values = values[np.isfinite(values)]
    if values.size < MIN_BALLS:
        return
    median = float(np.median(values))
    low, high = LAUNCH_SPEED_MEDIAN
    if not low <= median <= high:
        hint = " (in m/s?)" if median < low else " (in km/h?)"
        raise InputError("launch_speed", f"the median launch speed of the fly balls and "
                         f"home runs launched at 20-50 deg is {median:.4g} mph, outside "
                         f"{low:g}..{high:g} mph where it lies in real exports{hint}: the "
                         "values are not launch speeds in mph", source)


def check_distances_follow_launch(distance, model, source=None) -> None:
    """``InputError`` naming ``hit_distance_sc`` unless the measured distances vary
    with the model's predictions of the same launches as real balls' do
    (``MIN_DISTANCE_CORRELATION``, ``DISTANCE_SLOPE``): distances all alike,
    shuffled, or in another unit cannot calibrate the flight."""
    distance = np.asarray(distance, float)
    model = np.asarray(model, float)
    ok = np.isfinite(distance) & np.isfinite(model)
    distance, model = distance[ok], model[ok]
    if distance.size < 3 or np.ptp(model) == 0.0:
        return
    if np.ptp(distance) == 0.0:
        raise InputError("hit_distance_sc", f"every distance of the {distance.size} balls "
                         f"fitted is {distance[0]:g} ft: real distances vary with the launch "
                         f"(here the model predicts {np.min(model):.0f}..{np.max(model):.0f} "
                         "ft); these cannot calibrate the flight", source)
    r = float(np.corrcoef(distance, model)[0, 1])
    slope = float(np.polyfit(model, distance, 1)[0])
    low, high = DISTANCE_SLOPE
    if not (r >= MIN_DISTANCE_CORRELATION and low <= slope <= high):
        raise InputError("hit_distance_sc", f"the distances of the {distance.size} balls "
                         f"fitted do not vary with their launches as balls do: correlation "
                         f"{r:.2f} with the model's predictions (at least "
                         f"{MIN_DISTANCE_CORRELATION:g}; real exports 0.95-0.98), slope "
                         f"{slope:.2f} (within {low:g}..{high:g}; real exports 0.92-1.07): "
                         "distances in another unit, or of other balls? The scatter model of "
                         "the fit (one sigma about the flight) would not hold", source)


def predict(setup, table, scales=None) -> np.ndarray:
    """Predicted ``hit_distance_sc`` (ft) of every row at ``scales`` (default: the
    settings')."""
    from mcbat.stats.models.flight import FlightModel

    model = FlightModel(setup, table, 2, 0, scales)
    values, status = model.solve()
    d = values["hit_distance_sc"].reshape(-1, 2)[:, 0]
    return np.where(status.reshape(-1, 2)[:, 0] == 0, d, np.nan)
