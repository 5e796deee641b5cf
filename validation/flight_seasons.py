"""The flight of each season: Nathan's drag (and lift) fitted per season to real Statcast
distances with every ball in its own park and air, judged on files the fit never saw.

Run:  .venv/bin/python -m validation flight_seasons FILE... [--weather W.csv]
          [--write data/flight_seasons.csv] [--report REPORT.json] [--residuals R.parquet]

Every file is a Baseball Savant export (CSV, gzip or Parquet); a folder stands for its
``statcast_*.csv`` files. Pitches that appear in more
than one file (the same ``game_pk``, ``at_bat_number``, ``pitch_number``) are kept once,
from the first file that has them. Files whose balls are mostly home runs (searches for
home runs) are left out: a ball that became a home run carried farther than most balls of
its launch, so such a file would bias the drag low when fitted and the residuals low when
judged.

For each season with at least ``--min-balls`` outfield catches and home runs at 20-50 deg,
``drag_scale`` (``--free``, default ``drag_scale``) is fitted (``mcbat fit --flight``'s
fit: :func:`mcbat.papers.statcast.calibrate.calibrate`) with the regulation ball, Nathan's
average spin model and each ball's air (the games' weather from ``--weather``, else the
parks' climate; the recorded wind times ``--wind-scale``, by default the share that best
predicts the distances). The season table (``--write``) holds the fit to all of a season's
files. Out of sample, every ball is judged by a fit that never saw its file: the fit to
the season's other files (leave one file out); a season whose balls come from one file is
cut into five folds of games instead. Printed, and written to ``--report``: per season the
fitted values and, side by side, the residuals (predicted minus measured, ft) of the fly
balls and home runs of 20-50 deg in sample (the fit to all) and out of sample (each by the
fit without its file), for the fitted flight and for the published model in the same air;
out of sample also by calendar month and by game temperature, and the slope of the
residual against the temperature where the weather table gives it. ``--residuals`` writes
every judged ball with its out-of-sample residual.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

import harness
from mcbat.papers.statcast.calibrate import calibrate
from mcbat.papers.statcast.compare import eligible_window, residual_stats
from mcbat.papers.statcast.reproduce import (
    BALL,
    SETTINGS,
    air_per_ball,
    balls_in_their_air,
)
from mcbat.statcast import read
from mcbat.statcast.spin import nathan_average_spin
from mcbat.statcast.weather import read_weather
from mcbat.study.flight import SEASONS_FILE, fly_launches

KEY = ["game_pk", "at_bat_number", "pitch_number"]
FT, MPH, DEG, RPM = 0.3048, 0.44704, math.pi / 180, 2 * math.pi / 60


def read_files(paths) -> pd.DataFrame:
    """Every file's tidy rows with ``source_file``, duplicates across files dropped."""
    tables = []
    for path in paths:
        table = read(path)
        table["source_file"] = Path(path).name
        tables.append(table)
    table = pd.concat(tables, ignore_index=True)
    before = len(table)
    table = table.drop_duplicates(KEY, keep="first").reset_index(drop=True)
    table.attrs["duplicates_dropped"] = before - len(table)
    return table


#: A file whose compared balls are more than this share home runs was selected on the
#: outcome (a search for home runs): left out of fits and judgements alike.
HOME_RUN_SHARE = 0.5


def without_outcome_selected_files(balls):
    """``balls`` without the files selected on the outcome, and those files' home-run
    shares."""
    share = (balls["comparison"] == "home_run").groupby(balls["source_file"]).mean()
    selected = share[share > HOME_RUN_SHARE]
    kept = balls[~balls["source_file"].isin(selected.index)].reset_index(drop=True)
    return kept, {str(k): float(v) for k, v in selected.items()}


def folds(part: pd.DataFrame) -> tuple[np.ndarray, str]:
    """The fold of each ball of one season: its file, or (one file) one of five folds of
    games."""
    names = part["source_file"].to_numpy(object)
    if len(set(names)) > 1:
        return names, "by file"
    games = np.unique(part["game_pk"].to_numpy())
    fold_of = {g: i % 5 for i, g in enumerate(games)}
    return np.array([f"games {fold_of[g] + 1}/5" for g in part["game_pk"]], object), \
        "by game"


def predict(balls, drag_scale, lift_scale=1.0):
    """Predicted distance (ft) of each ball at its measured point, in its air."""
    backspin, sidespin = nathan_average_spin(balls["launch_angle"],
                                             balls["launch_spray_angle"], balls["handedness"])
    per_ball = air_per_ball(balls)
    per_ball.update(drag_scale=np.broadcast_to(drag_scale, len(balls)),
                    lift_scale=np.broadcast_to(lift_scale, len(balls)),
                    landing_height=balls["compare_height"].to_numpy(float) * FT)
    out, status = fly_launches(SETTINGS, BALL.mass, BALL.radius,
                               balls["launch_speed"].to_numpy(float) * MPH,
                               balls["launch_angle"].to_numpy(float) * DEG,
                               balls["launch_spray_angle"].to_numpy(float) * DEG,
                               np.asarray(backspin, float) * RPM,
                               np.asarray(sidespin, float) * RPM, per_ball=per_ball)
    return np.where(status == 0, out["hit_distance"] / FT, np.nan)


#: The wind scales tried by :func:`fit_wind_scale`.
WIND_SCALES = tuple(np.round(np.arange(0.0, 0.55, 0.05), 2))


def fit_wind_scale(balls):
    """The share of the recorded wind that best predicts the distances: the least rms
    residual about the median (published model) of the 20-50 deg fly balls and home runs
    that have a recorded wind, over :data:`WIND_SCALES`."""
    has_wind = (balls["wind_source"] == "weather").to_numpy(bool)
    part = balls[eligible_window(balls) & has_wind]
    if part.empty:
        return 1.0, {"rms": {}, "lines": ["no recorded wind (no weather table): wind scale "
                                          "not fitted"]}
    rms = {}
    for k in WIND_SCALES:
        scaled = part.assign(wind_x=part["wind_x"] * k, wind_y=part["wind_y"] * k)
        r = predict(scaled, 1.0) - scaled["hit_distance_sc"].to_numpy(float)
        r = r[np.isfinite(r)]
        rms[float(k)] = float(np.sqrt(np.mean((r - np.median(r)) ** 2))) if r.size \
            else float("nan")
    best = min(rms, key=rms.get)
    lines = [f"wind scale (the share of the recorded wind the ball feels): rms about the "
             f"median (ft) of the {len(part)} balls with a recorded wind:"]
    lines += [f"  {k:4.2f}: {v:5.1f}" + ("  <- least" if k == best else "")
              for k, v in rms.items()]
    return best, {"rms": rms, "lines": lines}


def window_stats(balls, drag_scale, lift_scale=1.0):
    """Residual statistics of the 20-50 deg fly balls and home runs of ``balls``."""
    window = balls[eligible_window(balls)]
    if window.empty:
        return residual_stats([])
    return residual_stats(predict(window, drag_scale, lift_scale)
                          - window["hit_distance_sc"].to_numpy(float))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument("--weather", default=None, metavar="W.csv")
    parser.add_argument("--free", default="drag_scale")
    parser.add_argument("--min-balls", type=int, default=40,
                        help="the fewest 20-50 deg catches and home runs a season's fit "
                             "takes (default 40)")
    parser.add_argument("--min-fold-balls", type=int, default=20,
                        help="the fewest a fit without one file takes to judge it "
                             "(default 20)")
    parser.add_argument("--wind-scale", type=float, default=None,
                        help="the share of the weather table's wind the balls feel "
                             "(default: fitted on the fitted files' balls)")
    parser.add_argument("--write", default=None, metavar="CSV")
    parser.add_argument("--report", default=None, metavar="JSON")
    parser.add_argument("--residuals", default=None, metavar="PARQUET")
    parser.add_argument("--figure", default=None, metavar="PNG",
                        help="the out-of-sample residuals by season, month and temperature")
    args = parser.parse_args(argv)
    args.files = [str(f) for name in args.files for f in (
        sorted(Path(name).glob("statcast_*.csv")) if Path(name).is_dir() else [name])]
    table = read_files(args.files)
    weather = None if args.weather is None else read_weather(args.weather)
    balls = balls_in_their_air(table, "the files", weather)
    balls, selected = without_outcome_selected_files(balls)
    for name, share in selected.items():
        print(f"left out: {name} ({share:.0%} of its balls are home runs: a search selected "
              f"on the outcome, whose balls carried farther than their launch says)")
    print(f"{len(table):,} distinct pitches of {len(args.files)} files "
          f"({table.attrs['duplicates_dropped']:,} duplicates dropped); {len(balls):,} "
          f"compared balls; air: {balls['air_source'].value_counts().to_dict()}")
    wind_scale, wind_scan = fit_wind_scale(balls) if args.wind_scale is None else (
        args.wind_scale, {})
    for line in wind_scan.get("lines", []):
        print(line)
    balls["wind_x"] = balls["wind_x"] * wind_scale
    balls["wind_y"] = balls["wind_y"] * wind_scale
    free = tuple(p.strip() for p in args.free.split(","))
    report, rows = {"files": [str(f) for f in args.files], "weather": args.weather,
                    "left_out_selected_on_outcome": selected, "free": list(free),
                    "wind_scale": wind_scale, "wind_scan": wind_scan.get("rms", {}),
                    "seasons": {}}, []
    print(f"{'season':>6} {'folds':>10} {'drag_scale':>15} {'lift_scale':>15} {'fit n':>6} "
          f"{'in-sample':>16} {'out of sample':>22} {'published, out':>15}")
    judged = []
    for season in sorted(balls["game_year"].dropna().unique()):
        part = balls[balls["game_year"] == season].reset_index(drop=True)
        if eligible_window(part).sum() < args.min_balls:
            print(f"{int(season):>6}: fewer than {args.min_balls} catches and home runs; "
                  "skipped")
            continue
        cal = fit_season(part, free, f"season {int(season)}")
        values = {p: cal.result.params[p] for p in free}
        errors = _half_widths({p: cal.result.intervals[p] for p in free})
        drag, lift = values.get("drag_scale", 1.0), values.get("lift_scale", 1.0)
        fold, how = folds(part)
        window = eligible_window(part)
        out_of_sample = np.full(len(part), np.nan)
        for name in np.unique(fold):
            rest = part[fold != name].reset_index(drop=True)
            if eligible_window(rest).sum() < args.min_fold_balls:
                continue  # too few balls left to fit without this file: not judged
            other = fit_season(rest, free, f"season {int(season)} without {name}")
            d = other.result.params.get("drag_scale", 1.0)
            lf = other.result.params.get("lift_scale", 1.0)
            here = (fold == name) & window
            out_of_sample[here] = (predict(part[here], d, lf)
                                   - part.loc[here, "hit_distance_sc"].to_numpy(float))
        in_sample = predict(part[window], drag, lift) - part.loc[
            window, "hit_distance_sc"].to_numpy(float)
        published = predict(part[window], 1.0, 1.0) - part.loc[
            window, "hit_distance_sc"].to_numpy(float)
        stats = {"in_sample": residual_stats(in_sample),
                 "out_of_sample": residual_stats(out_of_sample[window]),
                 "published": residual_stats(published)}
        frame = part[window].copy()
        frame["residual"] = out_of_sample[window]
        frame["fold"] = fold[window]
        judged.append(frame)
        entry = {"values": values, "errors": errors, "sigma_ft": cal.sigma,
                 "balls": cal.balls, "folds": how, "files": sorted(set(part["source_file"])),
                 "window_balls": int(window.sum()), **stats}
        report["seasons"][str(int(season))] = entry
        print(f"{int(season):>6} {how:>10} {drag:>8.3f}+-{errors.get('drag_scale', 0):.3f} "
              f"{lift:>8.3f}+-{errors.get('lift_scale', 0):.3f} {cal.balls:>6} "
              f"{_cell(stats['in_sample']):>16} {_cell(stats['out_of_sample']):>22} "
              f"{_cell(stats['published']):>15}")
        rows.append({"season": int(season), "drag_scale": round(drag, 4),
                     "drag_scale_error": round(errors.get("drag_scale", 0.0), 4),
                     "lift_scale": round(lift, 4),
                     "lift_scale_error": round(errors.get("lift_scale", 0.0), 4),
                     "sigma_ft": round(cal.sigma, 1), "balls": cal.balls,
                     "judged": stats["out_of_sample"]["n"], "wind_scale": wind_scale,
                     "spin_model": "nathan", "ball": BALL.preset,
                     "data": " ".join(entry["files"])})
    judged = pd.concat(judged, ignore_index=True)
    report["out_of_sample"] = pooled(judged)
    for line in report["out_of_sample"]["lines"]:
        print(line)
    if args.figure:
        from mcbat.papers.statcast.figures import residual_breakdowns

        figure = Path(args.figure)
        residual_breakdowns(figure.parent, judged, name=figure.name,
                            title="out of sample (each ball by the fit without its file): ")
        print(f"figure: {figure}")
    harness.record("flight_seasons", {
        "seasons": {k: {key: v[key] for key in ("values", "errors", "sigma_ft", "balls",
                                                "folds", "window_balls", "in_sample",
                                                "out_of_sample", "published")}
                    for k, v in report["seasons"].items()},
        "out_of_sample": {k: v for k, v in report["out_of_sample"].items() if k != "lines"},
        "wind_scale": wind_scale, "wind_scan": report["wind_scan"]},
        {"files": [Path(f).name for f in args.files], "weather": args.weather and
         Path(args.weather).name, "free": list(free),
         "left_out_selected_on_outcome": selected, "min_balls": args.min_balls,
         "min_fold_balls": args.min_fold_balls})
    if args.residuals:
        keep = ["source_file", "fold", "game_pk", "game_date", "game_year", "home_team",
                "launch_speed", "launch_angle", "spray_angle", "hit_distance_sc",
                "comparison", "temperature", "air_source", "residual"]
        judged[keep].to_parquet(args.residuals, index=False)
    if args.report:
        Path(args.report).write_text(json.dumps(report, indent=2) + "\n")
    if args.write:
        header = [line for line in _package_table_text().splitlines()
                  if line.startswith("#")]
        frame = pd.DataFrame(rows)
        Path(args.write).write_text("\n".join(header) + "\n" + frame.to_csv(index=False))
        print(f"season table written to {args.write}")
    return 0


def fit_season(part, free, source):
    """:func:`~mcbat.papers.statcast.calibrate.calibrate` of one season's balls (it fits
    the outfield catches and home runs launched at 20-50 deg)."""
    backspin, sidespin = nathan_average_spin(part["launch_angle"],
                                             part["launch_spray_angle"], part["handedness"])
    return calibrate(part.reset_index(drop=True), backspin, sidespin, ball=BALL,
                     settings=SETTINGS, free=free, intervals="profile", source=source)


def _cell(s):
    return "-" if not s["n"] else f"{s['median']:+.1f}/{s['rms']:.1f} ({s['n']})"


def pooled(judged: pd.DataFrame) -> dict:
    """Out-of-sample residuals of every judged ball by month and game temperature, the
    share compared, and the slope against the temperature where a weather table gave it."""
    r = judged["residual"].to_numpy(float)
    month = pd.to_datetime(judged["game_date"], errors="coerce").dt.month.to_numpy(float)
    out = {"all": residual_stats(r), "eligible": len(judged),
           "compared": int(np.isfinite(r).sum()),
           "month": {f"{int(m):02d}": residual_stats(r[month == m])
                     for m in np.unique(month[np.isfinite(month)])}}
    weather = (judged["air_source"] == "weather").to_numpy(bool) & np.isfinite(r)
    temperature = judged["temperature"].to_numpy(float)
    if weather.sum() > 10:
        slope, _ = np.polyfit(temperature[weather], r[weather], 1)
        resid = r[weather] - np.polyval(np.polyfit(temperature[weather], r[weather], 1),
                                        temperature[weather])
        sxx = np.sum((temperature[weather] - temperature[weather].mean()) ** 2)
        error = float(np.sqrt(np.sum(resid ** 2) / (weather.sum() - 2) / sxx))
        out["temperature_slope_ft_per_degF"] = {"value": float(slope), "error": error,
                                                "balls": int(weather.sum())}
    lines = [f"out of sample, all seasons: {_cell(out['all'])}; compared "
             f"{out['compared']} of {out['eligible']} eligible "
             f"({out['compared'] / max(out['eligible'], 1):.1%})",
             "  by month: " + ", ".join(f"{m} {_cell(v)}" for m, v in out["month"].items())]
    if "temperature_slope_ft_per_degF" in out:
        t = out["temperature_slope_ft_per_degF"]
        lines.append(f"  residual against the game temperature (weather table rows): "
                     f"{t['value']:+.3f} +- {t['error']:.3f} ft per degF ({t['balls']} balls)")
    out["lines"] = lines
    return out


def _half_widths(intervals) -> dict:
    """68 % errors (the mean of the lower and upper half-widths) of the fit's intervals."""
    out = {}
    for name, interval in intervals.items():
        lo, hi = interval.get("lower_error"), interval.get("upper_error")
        values = [v for v in (lo, hi) if v is not None and math.isfinite(v)]
        out[name] = float(np.mean(values)) if values else float("nan")
    return out


def _package_table_text() -> str:
    from importlib import resources

    return resources.files("mcbat.data").joinpath(SEASONS_FILE).read_text(encoding="utf-8")


if __name__ == "__main__":
    raise SystemExit(main())
