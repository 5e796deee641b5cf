"""``mcbat flight``: batted balls flown to the landing point."""

from __future__ import annotations

import dataclasses

from mcbat.cli.common import (
    CASES,
    EXIT_OK,
    Command,
    arg,
    each_case,
    flags,
    json_value,
    print_json,
    read_cases,
)

__all__ = ["COMMAND", "cmd_flight"]


def cmd_flight(args) -> int:
    """Fly the balls of ``args.file`` and print their landing points as JSON."""
    from mcbat.api import flight_case_from_dict, solve_flight

    def to_case(raw):
        case = flight_case_from_dict(raw)
        if args.scheme is None:
            return case
        return dataclasses.replace(case, settings=dataclasses.replace(
            case.settings, scheme=args.scheme))

    def fly(case):
        with flags("trajectory"):
            result = solve_flight(case, trajectory=args.trajectory).to_dict()
        return {k: json_value(v) for k, v in result.items()}

    source, raw_cases, single = read_cases(args.file)
    results = each_case(source, each_case(source, raw_cases, to_case), fly)
    print_json(results[0] if single else results)
    return EXIT_OK


COMMAND = Command(
    "flight", help="fly batted balls to the landing point (JSON: one ball or an array)",
    description="Read one JSON ball, or a JSON array of balls, from FILE (or '-' for "
                "stdin): launch_speed, launch_angle, spray_angle, backspin, sidespin, "
                "gyrospin, position, ball, atmosphere, model, spin_decay_time (a bare "
                "number in the field's units: speeds mph, angles deg, spins rpm, "
                "distances ft, temperature degF, pressure inHg; any value as "
                "{\"value\": ..., \"unit\": ...}; docs/flight.md). Prints "
                "hit_distance, hang_time, apex, landing_x, landing_y (ft, s) and their "
                "SI counterparts (*_m) as JSON, in the same order.",
    arguments=(
        CASES,
        arg("--trajectory", type=float, metavar="DT",
            help="add the flight sampled every DT seconds (t, x, y, z in s, m)"),
        arg("--scheme", choices=("adaptive", "sheet"),
            help="the integrator: adaptive (default) or the spreadsheet's fixed 0.01 s "
                 "steps, for comparison"),
    ),
    run=cmd_flight)
