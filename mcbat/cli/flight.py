"""``mcbat flight``: batted balls flown to the landing point."""

from __future__ import annotations

import dataclasses

from mcbat.cli.common import EXIT_OK, flags, json_value, located, print_json, read_cases
from mcbat.errors import InputError

__all__ = ["add_parser", "cmd_flight"]


def add_parser(sub) -> None:
    """Add ``mcbat flight`` to the subparsers ``sub``."""
    flight = sub.add_parser(
        "flight", help="fly batted balls to the landing point (JSON: one ball or an array)",
        description="Read one JSON ball, or a JSON array of balls, from FILE (or '-' for "
                    "stdin): launch_speed, launch_angle, spray_angle, backspin, sidespin, "
                    "gyrospin, position, ball, atmosphere, model, spin_decay_time (a bare "
                    "number in the field's units: speeds mph, angles deg, spins rpm, "
                    "distances ft, temperature degF, pressure inHg; any value as "
                    "{\"value\": ..., \"unit\": ...}; docs/flight.md). Prints "
                    "hit_distance, hang_time, apex, landing_x, landing_y (ft, s) and their "
                    "SI counterparts (*_m) as JSON, in the same order.")
    flight.add_argument("file", nargs="?", default="-", metavar="FILE|-")
    flight.add_argument("--trajectory", type=float, metavar="DT", default=None,
                        help="add the flight sampled every DT seconds (t, x, y, z in s, m)")
    flight.add_argument("--scheme", choices=("adaptive", "sheet"), default=None,
                        help="the integrator: adaptive (default) or the spreadsheet's fixed "
                             "0.01 s steps, for comparison")
    flight.set_defaults(func=cmd_flight)


def cmd_flight(args) -> int:
    """Fly the balls of ``args.file`` and print their landing points as JSON."""
    from mcbat.api import flight_case_from_dict, solve_flight

    source, raw_cases, single = read_cases(args.file)
    cases = []
    for index, raw in enumerate(raw_cases):
        try:
            case = flight_case_from_dict(raw)
            if args.scheme is not None:
                case = dataclasses.replace(case, settings=dataclasses.replace(
                    case.settings, scheme=args.scheme))
            cases.append(case)
        except InputError as err:
            raise located(err, f"{source}: case {index}") from None
    results = []
    for index, case in enumerate(cases):
        try:
            with flags("trajectory"):
                result = solve_flight(case, trajectory=args.trajectory).to_dict()
        except InputError as err:
            raise located(err, f"{source}: case {index}") from None
        results.append({k: json_value(v) for k, v in result.items()})
    print_json(results[0] if single else results)
    return EXIT_OK
