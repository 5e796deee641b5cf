"""``mcbat synth``: a noisy synthetic measurement table drawn from the model."""

from __future__ import annotations

import sys

from mcbat.cli.common import EXIT_OK, Command, arg, check_output, flags, int_option
from mcbat.cli.studies import study_file
from mcbat.errors import InputError

__all__ = ["COMMAND", "SYNTH_PARAMETERS", "cmd_synth"]

#: The parameters of ``mcbat.stats.measurements.synthesize`` that are flags.
SYNTH_PARAMETERS = ("rows", "seed", "e", "mu", "e_x", "speed_noise", "angle_noise",
                    "spin_noise", "impact_parameter_noise", "spin_in_noise", "input_noise")


def cmd_synth(args) -> int:
    """Draw the table and write it to ``args.out`` (or stdout, as CSV)."""
    from mcbat import load_study  # (a game study's [pitches] file is read too)
    from mcbat.stats.measurements import synthesize, write_table_atomic

    check_output(args.out, "--out", (".csv", ".parquet", ".pq"))
    with study_file(args.study, "--study") as path:
        study = load_study(path)
    input_noise = {}
    for item in args.input_noise:
        name, sep, value = item.partition("=")
        try:
            input_noise[name.strip()] = float(value) if sep else None
        except ValueError:
            input_noise[name.strip()] = None
        if input_noise[name.strip()] is None:
            raise InputError("--input-noise", f"expected NAME=SIGMA, got {item!r}")
    with flags(*SYNTH_PARAMETERS):
        table = synthesize(study, args.rows, args.seed, e=args.e, mu=args.mu, e_x=args.e_x,
                           speed_noise=args.speed_noise, angle_noise=args.angle_noise,
                           spin_noise=args.spin_noise,
                           impact_parameter_noise=args.impact_parameter_noise,
                           spin_in_noise=args.spin_in_noise, input_noise=input_noise)
    if args.out:
        write_table_atomic(table, args.out)
        print(f"{len(table)} rows written to {args.out}")
    else:
        table.to_csv(sys.stdout, index=False, float_format="%.10g")
    return EXIT_OK


COMMAND = Command(
    "synth", help="draw a noisy synthetic measurement table from the model",
    description="Sample the study's setup and nuisance scatter, solve with the given e* "
                "and mu, and add measurement noise: the kind of table an experiment "
                "produces (format: mcbat/stats/measurements.py).",
    arguments=(
        arg("--study", required=True, metavar="S.toml"),
        int_option("--rows", default=60, metavar="N"),
        int_option("--seed", default=0, metavar="S"),
        arg("--e", type=float, help="energetic restitution e*"),
        arg("--mu", type=float, help="friction coefficient"),
        arg("--e-x", type=float, dest="e_x",
            help="tangential restitution e_x (Cross & Nathan 2006; default: the study's, 0 "
                 "if unset = rigid)"),
        arg("--speed-noise", type=float,
            help="relative 1-sigma error of the exit (launch) speed (default 0.05; a game "
                 "study: 0.01)"),
        arg("--angle-noise", type=float,
            help="1-sigma error of the scattering angle (a game's launch and spray angles), "
                 "deg (default 3; a game study: 1)"),
        arg("--spin-noise", type=float, default=0.10,
            help="relative 1-sigma error of the outgoing spin (default 0.10)"),
        arg("--impact-parameter-noise", type=float, default=0.0, metavar="M",
            help="1-sigma error of the written impact parameter, m (default 0: exact); adds "
                 "an impact_parameter_err column"),
        arg("--spin-in-noise", type=float, default=0.0, metavar="RAD_S",
            help="1-sigma error of the written incoming spin, rad/s (default 0); adds a "
                 "spin_in_err column"),
        arg("--input-noise", action="append", default=[], metavar="NAME=SIGMA",
            help="1-sigma error of a written measured input, in the table's unit (a game: "
                 "pitch_speed, bat_speed in mph, attack_angle in deg, undercut in m); adds a "
                 "NAME_err column; repeatable"),
        arg("--out", metavar="M.csv", help="output file, .csv or .parquet (default: stdout)"),
    ),
    run=cmd_synth)
