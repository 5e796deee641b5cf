"""``mcbat calibrate``: the parameter at which a mean matches a measured number."""

from __future__ import annotations

import math

from mcbat.cli.common import EXIT_OK, Command, Group, arg, flags, print_json
from mcbat.cli.studies import study_file
from mcbat.errors import InputError

__all__ = ["COMMAND", "cmd_calibrate", "text_lines"]


def cmd_calibrate(args) -> int:
    """The paper's calibration of e*, or a study's (``--study``)."""
    if args.study is not None:
        return _calibrate_study(args)
    from mcbat.papers.cabo2012 import sec5
    from mcbat.papers.cabo2012.calibration import calibrate_restitution

    for flag in ("column", "samples"):
        if getattr(args, flag) is not None:
            raise InputError(f"--{flag}", "needs --study (without it, calibrate runs the "
                             "paper's Sec. V calibration)")
    if args.parameter != "e":
        raise InputError("--parameter", "needs --study (the paper's calibration is of e*)")
    if args.target is not None and not (math.isfinite(args.target) and args.target > 0):
        raise InputError("--target", f"must be a finite speed > 0 (m/s), got {args.target!r}")
    with flags("target"):
        result = calibrate_restitution(sec5.TARGET_SPEED if args.target is None
                                       else args.target)
    return _print(args, result.to_dict())


def _calibrate_study(args) -> int:
    from mcbat import load_study  # (a game study's [pitches] file is read too)
    from mcbat.stats.fit.calibrate import calibrate

    if args.target is None:
        raise InputError("--target", "required with --study: the measured mean")
    with study_file(args.study, "--study") as path:
        study = load_study(path)
    column = args.column or ("launch_speed" if study.kind == "game" else "exit_speed")
    with flags("target", "column", "parameter", "samples"):
        result = calibrate(study, column, args.target, args.parameter, samples=args.samples)
    return _print(args, result.to_dict())


def _print(args, result: dict) -> int:
    if args.format == "text":
        print("\n".join(text_lines(result)))
    else:
        print_json(result)
    return EXIT_OK


def text_lines(result: dict) -> list[str]:
    """A calibration (the ``to_dict`` of the paper's or of a study's) as lines of prose."""
    if "e_star" in result:  # the paper's Sec. V calibration
        return [f"e* = {result['e_star']:.7f} (e^2 = {result['loss_fraction']:.7f}) for an "
                f"exit speed of {result['target_speed']} m/s at theta = "
                f"{result['theta']:.6f} rad, w0 = {result['w0']:g} rad/s (reached "
                f"{result['exit_speed']:.9f} m/s)"]
    unit = f" {result['unit']}" if result.get("unit") else ""
    lines = [f"{result['parameter']} = {result['value']:.7g}: mean {result['column']} "
             f"{result['achieved']:.6g}{unit} (target {result['target']:.6g}{unit}) over "
             f"{result['samples']:,} rows of study {result['study']} (seed {result['seed']})"]
    if result.get("other_roots"):
        others = ", ".join(f"{v:.7g}" for v in result["other_roots"])
        lines.append(f"  other roots in the parameter's range: {others}")
    return lines


COMMAND = Command(
    "calibrate", help="find the e* (or mu, e_x) at which a study's mean matches a "
                      "measured number",
    description="With --study: solve (scipy brentq, common random numbers) for the "
                "parameter at which the mean COLUMN of the study's first --samples rows "
                "equals TARGET (in the column's unit: a drop test's exit_speed m/s, "
                "scattering_angle deg, spin_out rad/s; a game's launch_speed mph, "
                "launch_angle, spray_angle deg, spin_rate rpm). Without --study: the "
                "paper's calibration (Cabo et al. Sec. V): e* such that the exit speed "
                "at theta = pi/400 with no spin equals TARGET (m/s), with e^2 = 1 - e*^2. "
                "Prints JSON (the default, also --json), or with --text one line of "
                "prose.",
    arguments=(
        arg("--target", type=float, metavar="TARGET",
            help="the measured mean (without --study: the exit speed, m/s; default the "
                 "paper's 1.44629)"),
        arg("--study", metavar="STUDY.toml", help="the study to calibrate"),
        arg("--column", help="the observable whose mean is matched (default: exit_speed, or "
                             "launch_speed for a game study)"),
        arg("--parameter", default="e", help="e (default), mu or e_x"),
        arg("--samples", type=int,
            help="rows averaged (default: the study's samples, at most 20000)"),
        Group((arg("--json", action="store_const", const="json", dest="format",
                   help="print the result as one JSON object (the default)"),
               arg("--text", action="store_const", const="text", dest="format",
                   help="print the result as a line of prose")), exclusive=True),
    ),
    run=cmd_calibrate, defaults={"format": "json"})
