"""``mcbat reproduce``: a paper's results, end to end."""

from __future__ import annotations

from pathlib import Path

from mcbat.cli.common import EXIT_OK, QUIET, Command, arg, flags, int_option, progress, switch
from mcbat.errors import InputError

__all__ = ["COMMAND", "cmd_reproduce"]


def cmd_reproduce(args) -> int:
    """Run the reproduction ``args.paper`` into its results directory."""
    # The plain checks before the reproduction's imports (figures, fits: seconds of start-up,
    # a minute on a loaded machine, for what is a one-line refusal).
    for flag, value, most in (("--samples", args.samples, 10**12),
                              ("--threads", args.threads, 4096)):
        if value is not None and value < 1:
            raise InputError(flag, f"must be an integer >= 1, got {value}")
        if value is not None and value > most:
            raise InputError(flag, f"must be <= {most:,}, got {value:,}")
    for flag, value in (("--data", args.data), ("--weather", args.weather)):
        if args.paper != "statcast" and value is not None:
            raise InputError(flag, "applies to the statcast reproduction only")
    if args.paper == "statcast":
        return _reproduce_statcast(args)
    if args.out is None:
        args.out = "results"
    if args.paper == "sawicki2003":
        from mcbat.papers.sawicki2003.reproduce import reproduce as reproduce_sawicki

        if args.samples:
            raise InputError("--samples", "applies to the cabo2012 reproduction only "
                                          "(sawicki2003 writes no dataset)")
        with flags("out", "threads", "overwrite"):
            reproduce_sawicki(args.out, threads=args.threads, overwrite=args.overwrite)
        return EXIT_OK
    from mcbat.papers.cabo2012.reproduce import reproduce

    with flags("out", "samples", "threads", "overwrite"):
        reproduce(args.out, samples=args.samples, threads=args.threads,
                  progress=progress(args), overwrite=args.overwrite)
    return EXIT_OK


def _reproduce_statcast(args) -> int:
    from mcbat.papers.statcast.reproduce import reproduce as reproduce_statcast

    if args.samples:
        raise InputError("--samples", "applies to the cabo2012 reproduction only "
                                      "(statcast flies every ball of the file)")
    with flags("out", "threads", "overwrite", "weather"):
        reproduce_statcast(args.out or str(Path("results") / "statcast"), data=args.data,
                           weather_path=args.weather, threads=args.threads,
                           overwrite=args.overwrite)
    return EXIT_OK


COMMAND = Command(
    "reproduce", help="the main job: the paper's Sec. V with Monte Carlo scatter "
                      "(or another paper's results)",
    description="cabo2012 (the default): run studies/cross_nathan_2006.toml, calibrate "
                "e* on the paper's target exit speed, draw Figs. 2-8 and write a "
                "summary, all into one results directory. sawicki2003: the optimal "
                "swing against a fastball and a curveball (undercut x attack-angle "
                "scan with Monte Carlo scatter, flight to the landing point, rigid and "
                "compliant impact models) into DIR/sawicki2003. statcast: the flight "
                "model's distances against Statcast's hit_distance_sc for a Savant "
                "export's fly balls, line drives and home runs (--data; default the "
                "samples in data/) into DIR (default results/statcast).",
    arguments=(
        arg("paper", nargs="?", default="cabo2012",
            choices=("cabo2012", "sawicki2003", "statcast"),
            help="which reproduction (default: cabo2012); statcast: the flight model's "
                 "distances against measured Statcast distances (docs/flight.md)"),
        arg("--out", metavar="DIR",
            help="results directory (default: results; statcast: results/statcast)"),
        arg("--data", metavar="FILE", help="statcast: a Baseball Savant CSV export (default: "
                                           "the samples shipped in data/)"),
        arg("--weather", metavar="FILE",
            help="statcast: a per-game weather table (docs/parks-and-weather.md; default: "
                 "each park's climate normal for the month)"),
        int_option("--samples", metavar="N", help="Monte Carlo samples (default: the study's)"),
        int_option("--threads", metavar="K", help="kernel threads (default: all cores)"),
        switch("--overwrite", "replace a Monte Carlo dataset in DIR written with another "
               "sample count or by an older mcbat, and files named like the outputs "
               "(summary.json, figures/...) that mcbat did not write"),
        QUIET,
    ),
    run=cmd_reproduce)
