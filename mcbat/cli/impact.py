"""``mcbat impact``: single impacts given as JSON."""

from __future__ import annotations

import json
import sys

from mcbat.cli.common import CASES, EXIT_OK, Command, arg, each_case, flags, json_value, read_cases

__all__ = ["COMMAND", "cmd_impact"]


def cmd_impact(args) -> int:
    """Solve the cases of ``args.file`` and print their results as JSON."""
    from mcbat.api import SolverSettings, case_from_dict, solve_any

    with flags("tolerance"):  # checked before the input is read
        settings = SolverSettings() if args.tolerance is None else \
            SolverSettings(tolerance=args.tolerance)
    def solve(case):
        result = solve_any(case, settings, json_keys=True).to_dict()
        return {k: json_value(v) for k, v in result.items()}

    source, raw_cases, single = read_cases(args.file)
    cases = each_case(source, raw_cases, case_from_dict)  # a game case has pitch/swing keys
    results = each_case(source, cases, solve)
    json.dump(results[0] if single else results, sys.stdout, indent=2)
    sys.stdout.write("\n")
    return EXIT_OK


COMMAND = Command(
    "impact", help="solve impacts given as JSON (one case or an array of cases)",
    description="Read one JSON case, or a JSON array of cases, from FILE (or '-' for "
                "stdin) and print the results as JSON in the same order. A bat-frame "
                "case (ball, bat, contact, velocities; docs/impact.md): SI units, in "
                "the bat frame (an inertial frame with the bat's CM at the origin and z "
                "along its axis at contact), and so are its results. A game case "
                "(pitch and swing keys; docs/batting.md): "
                "a bare number of pitch and swing in the field's units (speeds mph, "
                "angles deg, spins rpm; pitch.speed at the plate or pitch.release_speed "
                "at release), of the bat and contact in SI, or any value with its unit "
                "({\"value\": 6, \"unit\": \"in\"}), in the field frame (x towards "
                "first base, y towards the pitcher, z up); its results are the batted ball in "
                "Statcast's units (launch_speed mph, angles deg, spins rpm), the "
                "field-frame velocities and spins in SI (\"field\"), and the bat-frame "
                "case and impact (\"bat_frame_case\", \"bat_frame\").",
    arguments=(
        CASES,
        arg("--tolerance", type=float, metavar="T",
            help="the kernel's tolerance: the local error allowed per slip step, relative "
                 "to the impact's speed and impulse scales, 0 < T < 1 (default 5e-9)"),
    ),
    run=cmd_impact)
