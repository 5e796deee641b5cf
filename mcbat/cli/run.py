"""``mcbat run``: a study into a Parquet dataset; the studies mcbat ships (the resource
package ``mcbat.studies``) run by name from any directory (``mcbat run game_fastball``)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from mcbat.cli.common import (
    EXIT_OK,
    QUIET,
    Command,
    arg,
    check_input_file,
    flags,
    int_option,
    progress,
    switch,
)
from mcbat.cli.studies import shipped_studies, study_file
from mcbat.errors import InputError

__all__ = ["COMMAND", "RUN_PARAMETERS", "cmd_run", "shipped_studies"]

#: The parameters of ``mcbat.runner.run_study`` that are flags of ``mcbat run``.
RUN_PARAMETERS = ("out", "samples", "seed", "threads", "chunk_size", "engine", "scheduler",
                  "workers", "overwrite", "summary_only", "columns", "tolerance")


class _ChunkSize(argparse.Action):
    """``--chunk-size``, whose help gives the runner's default chunk
    (``mcbat.runner.plan.DEFAULT_CHUNK_SIZE``), read only when the help is shown:
    the runner is not imported to build the parser."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)

    @property
    def help(self):
        from mcbat.runner.plan import DEFAULT_CHUNK_SIZE

        return f"rows per Parquet file (default: the study's, or {DEFAULT_CHUNK_SIZE:,})"

    @help.setter
    def help(self, value):  # argparse sets it; the property above gives it
        pass


def cmd_run(args) -> int:
    """Run the study ``args.study`` into a dataset and print the run's report."""
    if args.list:
        for name, description in shipped_studies().items():
            print(f"{name:<24} {description}".rstrip())
        return EXIT_OK
    if args.study is None:
        raise InputError("STUDY", "required: a study file, or the name of a study shipped "
                         "with mcbat (mcbat run --list)")
    from mcbat.runner import run_study
    from mcbat.study import load_study

    with study_file(args.study) as path:
        study = load_study(path)  # validates everything before anything is written
    if args.pitches is not None or args.swing_shift or args.league_contact:
        study = _with_pitches(study, args.pitches, args.swing_shift, args.league_contact)
    if args.columns is not None:
        with flags("columns"):
            study = study.with_overrides(columns=args.columns)
    if args.out is not None and not args.out.strip():
        raise InputError("--out", "must not be empty (give a directory or a URL; without "
                         "--out the dataset goes to results/<study name>)")
    out = args.out if args.out is not None else str(Path("results") / study.name)
    if out[:9].lower() == "memory://":
        raise InputError("--out", "memory:// keeps files in this process's memory: they would "
                         "vanish when the command ends (the Python API can use it); give a "
                         "directory or a persistent URL", out)
    with flags(*RUN_PARAMETERS):
        summary = run_study(study, out, samples=args.samples, seed=args.seed,
                            threads=args.threads, chunk_size=args.chunk_size,
                            overwrite=args.overwrite, progress=progress(args),
                            engine=args.engine, scheduler=args.scheduler,
                            workers=args.workers, summary_only=args.summary_only,
                            tolerance=args.tolerance)
    for line in summary.lines():
        print(line)
    return EXIT_OK


#: ``--swing-shift KEY=VALUE``: the keys and the units of their values (Statcast's).
SHIFT_UNITS = {"bat_speed": "mph", "attack_angle": "deg", "attack_direction": "deg"}


def _with_pitches(study, given, shifts, league=False):
    """``study`` drawing its pitches from the file ``given`` (``--pitches``, or None: the
    study's ``[pitches] file``) and with each drawn swing moved by ``shifts``
    (``--swing-shift``, over the study's ``[pitches.swing_shift]``), without its
    ``[pitches.player_levels]`` with ``league`` (``--league-contact``), every other setting
    as the study's. The dataset's config records the file's name and SHA-256 and the
    shifts."""
    from mcbat.runner.pitches import load_pitches
    from mcbat.study import Study

    flag = ("--pitches" if given is not None else "--swing-shift" if shifts
            else "--league-contact")
    if "pitches" not in study.definition():
        raise InputError(flag, f"the study draws no real pitches (it has no [pitches] "
                         f"section): {flag} works on a study that does, such as bat_tracking"
                         " or real_pitches")
    data = study.definition()
    if given is not None:
        path = Path(given)
        if not path.exists():
            raise InputError("--pitches", "no such file", given)
        check_input_file(path, "--pitches")
        data["pitches"]["file"] = str(path.resolve())
    if league and data["pitches"].pop("player_levels", None) is None:
        raise InputError("--league-contact", "the study has no [pitches.player_levels]: its "
                         "rows meet the league's contact already")
    for item in shifts:
        key, value = _swing_shift(item)
        data["pitches"].setdefault("swing_shift", {})[key] = {"value": value,
                                                              "unit": SHIFT_UNITS[key]}
    try:
        # (the file read and checked now, before anything is written)
        return load_pitches(Study.from_dict(data, source=study.source,
                                            text=study.source_text))
    except InputError as err:
        if err.field == "pitches.file" or (given is not None and err.field == "pitches"):
            # the file's fault (unreadable, or no row of it to draw): say so as the flag's
            hint = ("; or run a study that draws the swing, such as real_pitches"
                    if given is not None and "no bat tracking" in err.message else "")
            raise InputError("--pitches", err.message + hint) from None
        if err.field is not None and err.field.startswith("pitches.swing_shift"):
            raise InputError("--swing-shift", err.message) from None
        raise


def _swing_shift(item):
    """``KEY=VALUE`` of ``--swing-shift`` -> ``(key, value)`` (the value in
    :data:`SHIFT_UNITS`)."""
    key, sep, value = (part.strip() for part in item.partition("="))
    if not sep or key not in SHIFT_UNITS:
        raise InputError("--swing-shift", f"expected KEY=VALUE with KEY one of "
                         f"{', '.join(SHIFT_UNITS)}, got {item!r}")
    try:
        number = float(value.removesuffix(SHIFT_UNITS[key]).strip())
    except ValueError:
        raise InputError("--swing-shift", f"{key}: expected a number of "
                         f"{SHIFT_UNITS[key]}, got {value!r}") from None
    if not math.isfinite(number):
        raise InputError("--swing-shift", f"{key}: must be finite, got {value!r}")
    return key, number


COMMAND = Command(
    "run", help="run a Monte Carlo study (TOML) into a Parquet dataset directory",
    description="Sample the study's inputs, solve every impact with the parallel kernel "
                "and write a Parquet dataset (one file per chunk). An interrupted run "
                "resumes: complete chunk files are kept. STUDY is a TOML file, or the "
                "name of a study shipped with mcbat (mcbat run game_fastball, from any "
                "directory; --list names them).",
    arguments=(
        arg("study", metavar="STUDY.toml|NAME", nargs="?", default=None),
        switch("--list", "list the studies shipped with mcbat, and exit"),
        arg("--out", metavar="DIR", help="dataset directory, or a URL that pyarrow or fsspec "
                                         "can write (default: results/<study name>)"),
        arg("--pitches", metavar="FILE",
            help="draw the real pitches from FILE (a Savant export) instead of the study's "
                 "[pitches] file, with the study's filters and swing (mcbat run "
                 "bat_tracking --pitches my_export.csv)"),
        arg("--swing-shift", action="append", default=[], metavar="KEY=VALUE",
            help="what if every drawn swing were another: add VALUE to its bat_speed "
                 "(mph), attack_angle or attack_direction (deg), e.g. bat_speed=2; "
                 "repeatable; a study that draws its swings from the rows"),
        switch("--league-contact", "what if every batter and pitcher met the ball as the "
               "league does: leave out the study's [pitches.player_levels]"),
        int_option("--samples", metavar="N", help="number of impacts (default: the study's)"),
        int_option("--seed", metavar="S", help="random seed (default: the study's)"),
        int_option("--threads", metavar="K",
                   help="kernel threads (default: all cores); with --engine dask, numba "
                        "threads per worker (default: cores / workers, or 1 with "
                        "--scheduler)"),
        int_option("--chunk-size", metavar="C", action=_ChunkSize,
                   help="rows per Parquet file"),
        arg("--engine", choices=("local", "dask"), default="local",
            help="local: numba threads in this process (default); dask: one task per chunk "
                 "on a Dask cluster (docs/cluster.md)"),
        arg("--scheduler", metavar="ADDRESS",
            help="--engine dask: join the running Dask scheduler at ADDRESS "
                 "(tcp://host:8786); --out must be storage every worker shares"),
        int_option("--workers", metavar="N",
                   help="--engine dask: start a local cluster of N worker processes "
                        "(default: one per core)"),
        arg("--columns", metavar="A,B,...",
            help="store only these columns (and sample_id); overrides the study's [output] "
                 "columns"),
        switch("--summary-only", "compute the study's [summary] (binned statistics, "
               "_summary.parquet) without storing the rows"),
        switch("--overwrite", "replace an existing dataset written with another config"),
        arg("--tolerance", type=float, metavar="T",
            help="the kernel's tolerance: the local error allowed per slip step, relative "
                 "to the impact's scales, 0 < T < 1 (default: the study's [solver] "
                 "tolerance, else 5e-9); part of the dataset's config"),
        QUIET,
    ),
    run=cmd_run)
