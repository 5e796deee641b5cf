"""``mcbat replay``: every batted ball of a Savant export flown again under other
conditions (another park, temperature, wind, drag), with home runs called at the fences."""

from __future__ import annotations

import math

from mcbat.cli.common import (
    EXIT_OK,
    EXPORT,
    Command,
    arg,
    check_output,
    flags,
    print_json,
    switch,
    writing,
)

__all__ = ["COMMAND", "cmd_replay"]


def cmd_replay(args) -> int:
    """Replay the export's batted balls; print the summary, write --out."""
    from mcbat.dataset.tables import write_table
    from mcbat.statcast import read
    from mcbat.statcast.replay import Conditions, replay, replay_summary
    from mcbat.statcast.weather import read_weather

    check_output(args.out, "--out", (".csv", ".parquet"))
    with flags("park", "temperature", "wind_speed", "wind_direction", "drag_scale"):
        conditions = Conditions(park=args.park, temperature=args.temperature,
                                wind_speed=args.wind, wind_direction=args.wind_dir,
                                drag_scale=args.drag_scale)
    table = read(args.file)
    weather_table = None if args.weather is None else read_weather(args.weather)
    out = replay(table, conditions, weather_table=weather_table)
    summary = {"source": args.file, "conditions": conditions.describe(),
               **replay_summary(out)}
    if args.out:
        with writing(args.out):
            write_table(out, args.out, field="--out")
        summary["out"] = args.out
    if args.json:
        print_json({k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                    for k, v in summary.items()})
        return EXIT_OK
    s = summary

    def ft(value):
        return "-" if not math.isfinite(value) else f"{value:.1f} ft"

    print(f"{s['source']}: {s['balls']:,} batted balls replayed {s['conditions']}")
    print(f"  fly balls and home runs of 20-50 deg: {s['fly_balls_20_to_50_deg']:,}; median "
          f"carry {ft(s['median_distance_ft'])} (as they were "
          f"{ft(s['median_actual_distance_ft'])}), median change {ft(s['median_change_ft'])}")
    print(f"  home runs over the fences: expected {s['expected_home_runs']:.1f} (as they were "
          f"{s['actual_expected_home_runs']:.1f}; measured {s['measured_home_runs']}); "
          f"called {s['home_runs']} (as they were {s['actual_home_runs']}: gained "
          f"{s['home_runs_gained']}, lost {s['home_runs_lost']})"
          + (f"; {s['unknown_fence_height']} balls at a fence of unknown height not called"
             if s["unknown_fence_height"] else ""))
    if args.out:
        print(f"  written: {args.out}")
    return EXIT_OK


COMMAND = Command(
    "replay", help="what if: a Savant export's batted balls flown again at another park, "
                   "temperature, wind or drag, with home runs called at the fences",
    description="Fly every ball in play of a Baseball Savant export (with its measured "
                "launch speed, launch angle and spray angle; Nathan's average spin; the "
                "regulation ball) as it was (its park, season's ball and air) and under "
                "the conditions given, call home runs against the fences of the park "
                "flown at, and print the median change of the 20-50 deg fly balls and "
                "the home runs gained and lost (docs/flight.md).",
    arguments=(
        EXPORT,
        arg("--park", metavar="CODE",
            help="fly at this team's park (Statcast's home_team code: COL, MIA, ...)"),
        arg("--temperature", type=float, metavar="F", help="game temperature, degF"),
        arg("--wind", type=float, metavar="MPH", help="wind speed, mph (with --wind-dir)"),
        arg("--wind-dir", metavar="DIR", help="wind direction, Retrosheet's codes: tocf, "
                                              "fromcf, ltor, rtol, tolf, torf, fromlf, fromrf"),
        arg("--drag-scale", type=float, metavar="S",
            help="Nathan's spin-free drag times S, instead of each season's"),
        arg("--weather", metavar="W.csv", help="a per-game weather table "
                                               "(docs/parks-and-weather.md) for the balls as "
                                               "they were"),
        arg("--out", metavar="OUT.csv|OUT.parquet",
            help="write one row per ball (units in the CSV header or the Parquet metadata)"),
        switch("--json", "print the summary as JSON"),
    ),
    run=cmd_replay)
