"""The ``mcbat`` command.

Exit codes: 0 success, 2 user error (one line on stderr, no traceback; also ``mcbat
check`` on a dataset incomplete or inconsistent), 1 internal error, 4 the environment
failed mid-run, 130 interrupted, 141 the reader of stdout went away (``| head``).
``--debug`` shows the traceback of any error.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import math
import re
import sys
from pathlib import Path

from mcbat import __version__
from mcbat.errors import EnvironmentFailure, InputError

__all__ = ["build_parser", "main"]

EXIT_OK = 0
EXIT_INTERNAL = 1
EXIT_USER = 2
EXIT_ENVIRONMENT = 4  # the environment failed mid-run (a lost Dask scheduler)
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a reader that went away


class _ArgumentParser(argparse.ArgumentParser):
    """argparse that reports usage errors on one line with exit code 2."""

    def error(self, message):
        raise _UsageError(message)


class _UsageError(Exception):
    """A command-line usage error (bad flag or value): exit code 2."""


def _one_line(text: str) -> str:
    r"""``text`` with every line break and control character escaped (``\x85``,
    ``\u2028``): an error message that echoes the user's input stays one line."""
    import unicodedata

    return "".join(
        ch if ch == " " or unicodedata.category(ch) not in ("Cc", "Cf", "Zl", "Zp")
        else ch.encode("unicode_escape").decode("ascii") for ch in text)


def _reject_constant(name):
    raise ValueError(f"non-finite number {name} is not allowed")


_PARAMETER_IN_MESSAGE = re.compile(r'\b([a-z_]+)=("[^"]*"|[A-Za-z0-9_.:/-]+)')


@contextlib.contextmanager
def _flags(*parameters):
    """Report the library's errors about these Python parameters as their flags.

    The library names parameters (``chunk_size``) and writes the ones it mentions in call
    syntax (``overwrite=True``, ``scheduler=ADDRESS``); here they become ``--chunk-size``,
    ``--overwrite`` and ``--scheduler ADDRESS``.
    """
    flags = {name: "--" + name.replace("_", "-") for name in parameters}

    def render(match):
        name, value = match.group(1), match.group(2)
        if name not in flags:
            return match.group(0)
        if value == "True":
            return flags[name]
        return f"{flags[name]} {value.strip(chr(34))}"

    try:
        yield
    except InputError as err:
        raise InputError(flags.get(err.field, err.field),
                         _PARAMETER_IN_MESSAGE.sub(render, err.message), err.source) from None


def _read_cases(path):
    """Parse ``path`` (or ``-`` for stdin) as one JSON case or a JSON array of cases."""
    source = "<stdin>" if path == "-" else path
    try:
        if path == "-":  # bytes: the encoding is checked below (a text stdin has none)
            stream = getattr(sys.stdin, "buffer", None)
            raw = stream.read() if stream is not None else sys.stdin.read().encode()
        else:
            with open(path, "rb") as handle:
                raw = handle.read()
        text = raw.decode("utf-8-sig")  # JSON is UTF-8 (RFC 8259); a BOM is tolerated
    except OSError as err:
        raise InputError(None, f"cannot read input: {err.strerror}", source) from None
    except UnicodeDecodeError as err:
        raise InputError(None, f"not UTF-8 text (byte {err.start}); JSON input must be UTF-8",
                         source) from None
    try:
        data = json.loads(text, parse_constant=_reject_constant)
    except ValueError as err:
        raise InputError(None, f"not valid JSON: {err}", source) from None
    except RecursionError:
        raise InputError(None, "not valid JSON: nested too deeply", source) from None
    single = isinstance(data, dict)
    cases = [data] if single else data
    if not isinstance(cases, list) or not cases:
        raise InputError(None, "expected a JSON object (one case) or a non-empty array of "
                         "cases", source)
    return source, cases, single


def _json_value(value):
    """``value`` with non-finite floats (also inside lists and dicts) as None: strict JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple)):
        return [_json_value(v) for v in value]
    if isinstance(value, dict):
        return {k: _json_value(v) for k, v in value.items()}
    return value


def cmd_impact(args) -> int:
    from mcbat.api import SolverSettings, case_from_dict, solve_any

    with _flags("tolerance"):  # checked before the input is read
        settings = SolverSettings() if args.tolerance is None else \
            SolverSettings(tolerance=args.tolerance)
    source, raw_cases, single = _read_cases(args.file)
    cases = []
    for index, raw in enumerate(raw_cases):
        try:
            cases.append(case_from_dict(raw))  # a game case has pitch/swing keys
        except InputError as err:
            raise InputError(err.field, err.message, f"{source}: case {index}") from None
    results = []
    for index, case in enumerate(cases):
        try:
            result = solve_any(case, settings, json_keys=True).to_dict()
        except InputError as err:
            raise InputError(err.field, err.message, f"{source}: case {index}") from None
        results.append({k: _json_value(v) for k, v in result.items()})
    payload = results[0] if single else results
    json.dump(payload, sys.stdout, indent=2)
    sys.stdout.write("\n")
    return EXIT_OK


def cmd_flight(args) -> int:
    from mcbat.api import flight_case_from_dict, solve_flight

    source, raw_cases, single = _read_cases(args.file)
    cases = []
    for index, raw in enumerate(raw_cases):
        try:
            case = flight_case_from_dict(raw)
            if args.scheme is not None:
                case = dataclasses.replace(case, settings=dataclasses.replace(
                    case.settings, scheme=args.scheme))
            cases.append(case)
        except InputError as err:
            raise InputError(err.field, err.message, f"{source}: case {index}") from None
    results = []
    for index, case in enumerate(cases):
        try:
            with _flags("trajectory"):
                result = solve_flight(case, trajectory=args.trajectory).to_dict()
        except InputError as err:
            raise InputError(err.field, err.message, f"{source}: case {index}") from None
        results.append({k: _json_value(v) for k, v in result.items()})
    json.dump(results[0] if single else results, sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")
    return EXIT_OK


RUN_PARAMETERS = ("out", "samples", "seed", "threads", "chunk_size", "engine", "scheduler",
                  "workers", "overwrite", "summary_only", "columns", "tolerance")


def cmd_run(args) -> int:
    from mcbat.runner import run_study
    from mcbat.study import load_study

    study = load_study(args.study)  # validates everything before anything is written
    if args.columns is not None:
        with _flags("columns"):
            study = study.with_overrides(columns=args.columns)
    if args.out is not None and not args.out.strip():
        raise InputError("--out", "must not be empty (give a directory or a URL; without "
                         "--out the dataset goes to results/<study name>)")
    out = args.out if args.out is not None else str(Path("results") / study.name)
    if re.match(r"(?i)memory://", out):
        raise InputError("--out", "memory:// keeps files in this process's memory: they would "
                         "vanish when the command ends (the Python API can use it); give a "
                         "directory or a persistent URL", out)
    with _flags(*RUN_PARAMETERS):
        summary = run_study(study, out, samples=args.samples, seed=args.seed,
                            threads=args.threads, chunk_size=args.chunk_size,
                            overwrite=args.overwrite, progress=not args.quiet,
                            engine=args.engine, scheduler=args.scheduler,
                            workers=args.workers, summary_only=args.summary_only,
                            tolerance=args.tolerance)
    for line in summary.lines():
        print(line)
    return EXIT_OK


def cmd_check(args) -> int:
    from mcbat.dataset.check import check_dataset

    result = check_dataset(args.directory, checksums=not args.quick)
    for line in result.lines():
        print(line)
    # A damaged, incomplete or unverifiable dataset is bad input to every command that
    # reads it: exit 2, the report above on stdout, its first problem as the error line.
    problem = result.first_problem()
    if problem is not None:
        raise InputError(None, problem, str(result.directory))
    return EXIT_OK


def cmd_reproduce(args) -> int:
    # The plain checks before the reproduction's imports (figures, fits: seconds of start-up,
    # a minute on a loaded machine, for what is a one-line refusal).
    for flag, value, most in (("--samples", args.samples, 10**12),
                              ("--threads", args.threads, 4096)):
        if value is not None and value < 1:
            raise InputError(flag, f"must be an integer >= 1, got {value}")
        if value is not None and value > most:
            raise InputError(flag, f"must be <= {most:,}, got {value:,}")
    if args.paper != "statcast" and args.data is not None:
        raise InputError("--data", "applies to the statcast reproduction only")
    if args.paper == "statcast":
        return _reproduce_statcast(args)
    if args.out is None:
        args.out = "results"
    if args.paper == "sawicki2003":
        from mcbat.papers.sawicki2003.reproduce import reproduce as reproduce_sawicki

        if args.samples:
            raise InputError("--samples", "applies to the cabo2012 reproduction only "
                                          "(sawicki2003 writes no dataset)")
        with _flags("out", "threads", "overwrite"):
            reproduce_sawicki(args.out, threads=args.threads, overwrite=args.overwrite)
        return EXIT_OK
    from mcbat.papers.cabo2012.reproduce import reproduce

    with _flags("out", "samples", "threads", "overwrite"):
        reproduce(args.out, samples=args.samples, threads=args.threads,
                  progress=not args.quiet, overwrite=args.overwrite)
    return EXIT_OK


def _reproduce_statcast(args) -> int:
    from mcbat.papers.statcast.reproduce import reproduce as reproduce_statcast

    if args.samples:
        raise InputError("--samples", "applies to the cabo2012 reproduction only "
                                      "(statcast flies every ball of the file)")
    with _flags("out", "threads", "overwrite"):
        reproduce_statcast(args.out or str(Path("results") / "statcast"), data=args.data,
                           threads=args.threads, overwrite=args.overwrite)
    return EXIT_OK


def cmd_calibrate(args) -> int:
    from mcbat.papers.cabo2012 import sec5
    from mcbat.papers.cabo2012.calibration import calibrate_restitution

    if args.study is not None:
        return _calibrate_study(args)
    for flag in ("column", "samples"):
        if getattr(args, flag) is not None:
            raise InputError(f"--{flag}", "needs --study (without it, calibrate runs the "
                             "paper's Sec. V calibration)")
    if args.parameter != "e":
        raise InputError("--parameter", "needs --study (the paper's calibration is of e*)")
    if args.target is not None and not (math.isfinite(args.target) and args.target > 0):
        raise InputError("--target", f"must be a finite speed > 0 (m/s), got {args.target!r}")
    with _flags("target"):
        result = calibrate_restitution(sec5.TARGET_SPEED if args.target is None
                                       else args.target)
    json.dump(_json_value(result.to_dict()), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")
    return EXIT_OK


def _calibrate_study(args) -> int:
    from mcbat import load_study  # (a game study's [pitches] file is read too)
    from mcbat.stats.calibrate import calibrate

    if args.target is None:
        raise InputError("--target", "required with --study: the measured mean")
    study = load_study(args.study)
    column = args.column or ("launch_speed" if study.kind == "game" else "exit_speed")
    with _flags("target", "column", "parameter", "samples"):
        result = calibrate(study, column, args.target, args.parameter, samples=args.samples)
    json.dump(_json_value(result.to_dict()), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")
    return EXIT_OK


def _check_output(path, flag, suffixes):
    """Refuse an output path that cannot be written, before any work is done."""
    import os

    target = Path(path)
    if target.suffix.lower() not in suffixes:
        raise InputError(flag, f"unsupported file type {target.suffix or '(none)'!r} for "
                         f"{path} (use one of: {', '.join(suffixes)})")
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(flag, f"cannot write {path}: no such directory {str(parent)!r}")
    if target.is_dir():
        raise InputError(flag, f"cannot write {path}: it is a directory")
    if not os.access(parent, os.W_OK):
        raise InputError(flag, f"cannot write {path}: the directory is not writable")


SYNTH_PARAMETERS = ("rows", "seed", "e", "mu", "e_x", "speed_noise", "angle_noise",
                    "spin_noise", "impact_parameter_noise", "spin_in_noise", "input_noise")


def cmd_synth(args) -> int:
    from mcbat import load_study  # (a game study's [pitches] file is read too)
    from mcbat.stats.measurements import synthesize, write_table_atomic

    if args.out:
        _check_output(args.out, "--out", (".csv", ".parquet", ".pq"))
    study = load_study(args.study)
    input_noise = {}
    for item in args.input_noise:
        name, sep, value = item.partition("=")
        try:
            input_noise[name.strip()] = float(value) if sep else None
        except ValueError:
            input_noise[name.strip()] = None
        if input_noise[name.strip()] is None:
            raise InputError("--input-noise", f"expected NAME=SIGMA, got {item!r}")
    with _flags(*SYNTH_PARAMETERS):
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


RESIDUAL_FORMATS = (".png", ".pdf", ".svg")


def _fit_flight(args) -> int:
    from mcbat.papers.statcast.calibrate import calibrate_file

    for flag in ("study", "residuals", "draws"):
        if getattr(args, flag) is not None:
            raise InputError(f"--{flag}", "not with --flight (the flight fit flies each "
                             "ball of --data once)")
    if args.bootstrap:
        raise InputError("--bootstrap", "not with --flight")
    with _flags("free", "intervals", "spin_model"):
        result = calibrate_file(args.data, free=args.free, intervals=args.intervals,
                                spin_model=args.spin_model or "nathan")
    if args.json:
        json.dump(_json_value(result.to_dict()), sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return EXIT_OK
    print(f"fit of {', '.join(result.result.params)} to {result.balls} outfield catches and "
          f"home runs of {result.source} (flight model nathan, spin model "
          f"{result.spin_model}):")
    for line in result.lines():
        print(line)
    return EXIT_OK


def cmd_fit(args) -> int:
    from mcbat import load_study  # (a game study's [pitches] file is read too)
    from mcbat.stats.fit import check_bootstrap, fit
    from mcbat.stats.likelihood import check_free
    from mcbat.stats.measurements import read_measurements
    from mcbat.stats.model_choice import compare_models

    if args.flight:
        return _fit_flight(args)
    if args.population:
        return _fit_population(args)
    if args.spin_model is not None:
        raise InputError("--spin-model", "applies to --flight only")
    if args.study is None:
        raise InputError("--study", "required (or --flight: the flight model's drag and "
                         "lift against measured distances)")
    if args.data is None:
        raise InputError("--data", "required")
    free = _fit_options(args, check_free, check_bootstrap)
    if args.residuals:
        _check_output(args.residuals, "--residuals", RESIDUAL_FORMATS)
    study = load_study(args.study)
    table = read_measurements(args.data)
    if "statcast" in table.attrs:  # a Savant export: say which rows the fit uses
        kept = table.attrs["statcast"]
        print(f"mcbat: {args.data}: Statcast export: {kept['used']:,} of {kept['rows']:,} "
              f"pitches used (balls in play with launch speed, angle, spray and plate "
              f"speed{' and bat tracking' if 'bat_speed' in table else ''}); dropped: "
              f"{kept['not_in_play']:,} not in play, {kept['no_launch']:,} without launch, "
              f"{kept['foul_territory']:,} fielded in foul territory, "
              f"{kept['no_plate_speed']:,} without plate speed, {kept['no_bat_tracking']:,} "
              f"without bat tracking", file=sys.stderr)
    with _flags("free", "bootstrap", "draws", "seed", "intervals"):
        result = fit(study, table, free, bootstrap=args.bootstrap, draws=args.draws,
                     seed=args.seed, intervals=args.intervals, input_prior=args.input_prior,
                     likelihood=args.likelihood)
        comparison = None if args.no_compare else compare_models(
            study, table, free, draws=args.draws, seed=args.seed, fitted=result,
            input_prior=args.input_prior, likelihood=args.likelihood)
    if args.residuals:
        from mcbat.stats.figures import fig_fit_residuals

        fig_fit_residuals(args.residuals, table, result)
    if args.json:
        out = result.to_dict()
        if comparison is not None:
            out["model_comparison"] = comparison.to_dict()
        json.dump(_json_value(out), sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return EXIT_OK
    print(f"fit of {', '.join(free)} to {len(table)} rows of {args.data} "
          f"(study {study.name}):")
    for line in result.lines():
        print(line)
    print(f"  chi2 / dof = {result.chi2:.1f} / {result.dof}, p-value = {result.p_value:.3f}")
    for warning in result.warnings:
        print(f"  note: {warning}")
    if comparison is not None:
        print("\n".join(comparison.lines()))
    return EXIT_OK


def _fit_population(args) -> int:
    """``mcbat fit --population``: a game study's distributions against batted balls
    (docs/population.md)."""
    from mcbat import load_study
    from mcbat.statcast import read
    from mcbat.stats.population import fit_population

    for flag, value in (("--study", args.study), ("--data", args.data),
                        ("--free", args.free)):
        if value is None:
            raise InputError(flag, "required with --population")
    if args.figure:
        _check_output(args.figure, "--figure", RESIDUAL_FORMATS)
    study = load_study(args.study)
    table = read(args.data)
    with _flags("free", "draws", "seed", "bins", "observables", "engine"):
        result = fit_population(study, table, [f for f in args.free.split(",") if f],
                                draws=args.draws, bins=args.bins, seed=args.seed,
                                observables=args.observables.split(","), engine=args.engine)
    if args.figure:
        from mcbat.stats.population_figure import fig_population

        fig_population(args.figure, result)
    if args.json:
        json.dump(_json_value(result.to_dict()), sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return EXIT_OK
    print(f"population fit of {args.free} to {result.rows} batted balls of {args.data} "
          f"(study {study.name}; {result.draws:,} template draws, effective "
          f"{result.effective_draws:,.0f}):")
    print("\n".join(result.lines()))
    print(f"  chi2 / dof = {result.chi2:.1f} / {result.dof}, p-value = {result.p_value:.3f}")
    for warning in result.warnings:
        print(f"  note: {warning}")
    return EXIT_OK


def _fit_options(args, check_free, check_bootstrap):
    """The fit's free parameters; every option checked before any work."""
    with _flags("free", "bootstrap", "draws", "seed"):
        free = tuple(check_free(args.free or "e,mu"))
        check_bootstrap(args.bootstrap)
        if args.draws is not None and args.draws < 4:
            raise InputError("draws", f"must be an integer >= 4, got {args.draws}")
        if args.seed < 0:
            raise InputError("seed", f"must be an integer >= 0, got {args.seed}")
        if args.seed > 2**63 - 1:
            raise InputError("seed", f"must be <= 2**63 - 1, got {args.seed}")
    return free


def cmd_statcast(args) -> int:
    from mcbat.statcast import read, summarize, write

    if args.out:
        _check_output(args.out, "--out", (".parquet", ".pq"))
    table = read(args.file)
    summary = summarize(table)
    if args.out:
        try:
            write(table, args.out)
        except OSError as err:
            raise InputError("--out", f"cannot write: {err.strerror or err}",
                             args.out) from None
        summary["out"] = args.out
    if args.json:
        json.dump(_json_value(summary), sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return EXIT_OK
    print("\n".join(_statcast_lines(summary)))
    return EXIT_OK


def cmd_infer(args) -> int:
    from mcbat.inference import infer_spin, write
    from mcbat.statcast import balls_in_play, read

    if args.out:
        _check_output(args.out, "--out", (".parquet", ".pq"))
    pitches = read(args.file)
    balls = pitches[balls_in_play(pitches)]
    spin = infer_spin(balls)
    if args.out:
        try:
            write(balls, spin, args.out)
        except OSError as err:
            raise InputError("--out", f"cannot write: {err.strerror or err}",
                             args.out) from None
    counts = ", ".join(f"{k} {v:,}" for k, v in spin.attrs["status_counts"].items() if v)
    ok = spin["inference_status"] == "converged"
    print(f"{args.file}: {len(balls):,} balls in play: {counts or 'none'}")
    if ok.any():
        print(f"  median backspin {spin.loc[ok, 'backspin'].median():.0f} rpm, spin rate "
              f"{spin.loc[ok, 'spin_rate'].median():.0f} rpm (assumptions: "
              "docs/spin_inference.md)")
    if args.out:
        print(f"  written: {args.out}")
    return EXIT_OK


COMPARE_PARAMETERS = ("permutations", "seed", "max_rows", "plane_rows", "columns", "units")


def cmd_compare(args) -> int:
    from mcbat.stats.compare import (
        check_settings,
        compare,
        fig_compare,
        read_measured,
        read_simulated,
    )

    if args.figure:
        _check_output(args.figure, "--figure", RESIDUAL_FORMATS)
    for path in (args.dataset, *args.measured):  # before the readers' imports (seconds)
        if "://" not in path and not Path(path).exists():
            raise InputError(None, "no such file or directory", path)
    units = {}
    for item in args.units:
        name, sep, unit = (part.strip() for part in item.partition("="))
        if not (sep and name and unit):
            raise InputError("--units", f"expected COLUMN=UNIT, got {item!r}")
        units[name] = unit
    columns = None if args.columns is None else \
        [c.strip() for c in args.columns.split(",") if c.strip()]
    with _flags(*COMPARE_PARAMETERS):
        check_settings(args.permutations, args.seed, args.max_rows, args.plane_rows, units)
        if columns == []:
            raise InputError("columns", "no column given")
    simulated = read_simulated(args.dataset)
    measured = read_measured(args.measured, units)
    try:
        with _flags(*COMPARE_PARAMETERS):
            result = compare(simulated, measured, columns, permutations=args.permutations,
                             seed=args.seed, max_rows=args.max_rows,
                             plane_rows=args.plane_rows)
    except InputError as err:  # a column's problem: name the measured table(s)
        message = re.sub(r"units=\{'([^']+)': '([^']+)'\}", r"--units \1=\2", err.message)
        where = args.dataset if "of the simulated dataset" in message else \
            ", ".join(args.measured)
        raise InputError(err.field, message, err.source or where) from None
    result.simulated = {"path": args.dataset, "rows": len(simulated),
                        "study": simulated.attrs.get("mcbat", {}).get("study_name")}
    result.measured = {"rows": len(measured), "sources": measured.attrs["sources"]}
    if args.figure:
        fig_compare(args.figure, simulated, measured, result)
    if args.json:
        out = result.to_dict()
        if args.figure:
            out["figure"] = args.figure
        json.dump(_json_value(out), sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return EXIT_OK
    study = result.simulated["study"]
    print(f"simulated: {args.dataset} ({f'study {study}, ' if study else ''}"
          f"{len(simulated):,} rows)")
    for source in measured.attrs["sources"]:
        what = (f"{source['rows']:,} balls in play of {source['pitches']:,} pitches"
                if source["kind"] == "statcast" else f"{source['rows']:,} rows")
        print(f"measured: {source['path']} ({source['kind']}, {what})")
    print("\n".join(result.lines()))
    if args.figure:
        print(f"figure: {args.figure}")
    return EXIT_OK


def _statcast_lines(summary):
    """The summary of ``mcbat statcast`` as text lines."""
    seasons = ", ".join(str(y) for y in summary["seasons"]) or "none"
    types = ", ".join(f"{k} {v:,}" for k, v in summary["pitch_types"].items())
    lines = [f"{summary['source']}: {summary['rows']:,} pitches, seasons {seasons}",
             f"  pitches by type: {types or 'none'}",
             f"  balls in play: {summary['balls_in_play']:,} ({summary['with_launch']:,} "
             "with launch speed and angle)",
             f"  rows with a distance (hit_distance_sc): {summary['with_distance']:,}",
             f"  rows with bat tracking (bat_speed): {summary['with_bat_tracking']:,}"]
    for kind, entry in summary["plate"].items():
        if entry["pitch_speed"] is None or entry["pitches"] < 10:
            continue
        parts = [f"{entry[c]['median']:.1f}" + (f" (sd {entry[c]['sd']:.1f})"
                                                  if entry[c]["sd"] is not None else "")
                 for c in ("pitch_speed", "vertical_approach_angle",
                           "horizontal_approach_angle")]
        lines.append(f"  {kind} at the plate (median): {parts[0]} mph, vertical approach "
                     f"{parts[1]} deg, horizontal {parts[2]} deg")
    check = summary.get("attack_direction_check")
    if check:
        lines.append(f"  attack_direction vs spray towards the opposite field: correlation "
                     f"{check['correlation']:+.2f} over {check['rows']:,} balls in play "
                     "(> 0: the sign convention of docs/statcast.md holds)")
    if summary.get("missing_columns"):
        lines.append(f"  columns this export lacks (NaN): {', '.join(summary['missing_columns'])}")
    for column, bad in summary.get("non_numeric", {}).items():
        where = f" (first at line {bad['line']}: {bad['value']!r})" if "line" in bad else ""
        lines.append(f"  {column}: {bad['cells']:,} non-numeric cell(s) set to NaN{where}")
    if summary.get("elevation_missing"):
        teams = ", ".join(f"{k} {v:,}" for k, v in summary["elevation_missing"].items())
        unknown = ", ".join(summary.get("unknown_home_teams", {}))
        lines.append(f"  rows without a park elevation (NaN), by home_team: {teams}"
                     + (f"; not in the park table: {unknown}" if unknown else ""))
    if summary.get("out"):
        lines.append(f"  tidy table written to {summary['out']}")
    return lines


def build_parser() -> argparse.ArgumentParser:
    """The ``mcbat`` argument parser, one subcommand per job."""
    parser = _ArgumentParser(
        prog="mcbat",
        description="Monte Carlo study of rigid ball-bat impacts with Coulomb friction.",
    )
    parser.add_argument("--debug", action="store_true",
                        help="show Python tracebacks for errors")
    parser.add_argument("--version", action="version", version=f"mcbat {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_ArgumentParser)
    impact = sub.add_parser(
        "impact", help="solve impacts given as JSON (one case or an array of cases)",
        description="Read one JSON case, or a JSON array of cases, from FILE (or '-' for "
                    "stdin) and print the results as JSON in the same order. SI units, lab "
                    "frame (bat CM at the origin, z along the bat axis).")
    impact.add_argument("file", nargs="?", default="-", metavar="FILE|-")
    impact.add_argument("--tolerance", type=float, default=None, metavar="T",
                        help="the kernel's tolerance: the local error allowed per slip "
                             "step, relative to the impact's speed and impulse scales, "
                             "0 < T < 1 (default 5e-9)")
    impact.set_defaults(func=cmd_impact)

    flight = sub.add_parser(
        "flight", help="fly batted balls to the landing point (JSON: one ball or an array)",
        description="Read one JSON ball, or a JSON array of balls, from FILE (or '-' for "
                    "stdin): launch_speed, launch_angle, spray_angle, backspin, sidespin, "
                    "gyrospin, position, ball, atmosphere, model, spin_decay_time (values in "
                    "SI or as {\"value\": ..., \"unit\": ...}; docs/flight.md). Prints "
                    "hit_distance, hang_time, apex, landing_x, landing_y (ft, s) and their "
                    "SI counterparts (*_m) as JSON, in the same order.")
    flight.add_argument("file", nargs="?", default="-", metavar="FILE|-")
    flight.add_argument("--trajectory", type=float, metavar="DT", default=None,
                        help="add the flight sampled every DT seconds (t, x, y, z in s, m)")
    flight.add_argument("--scheme", choices=("adaptive", "sheet"), default=None,
                        help="the integrator: adaptive (default) or the spreadsheet's fixed "
                             "0.01 s steps, for comparison")
    flight.set_defaults(func=cmd_flight)

    run = sub.add_parser(
        "run", help="run a Monte Carlo study (TOML) into a Parquet dataset directory",
        description="Sample the study's inputs, solve every impact with the parallel kernel "
                    "and write a Parquet dataset (one file per chunk). An interrupted run "
                    "resumes: complete chunk files are kept.")
    run.add_argument("study", metavar="STUDY.toml")
    run.add_argument("--out", metavar="DIR", help="dataset directory, or a URL that pyarrow "
                     "or fsspec can write (default: results/<study name>)")
    run.add_argument("--samples", type=_int_arg("--samples"), metavar="N",
                     help="number of impacts (default: the study's)")
    run.add_argument("--seed", type=_int_arg("--seed"), metavar="S",
                     help="random seed (default: the study's)")
    run.add_argument("--threads", type=_int_arg("--threads"), metavar="K",
                     help="kernel threads (default: all cores); with --engine dask, numba "
                          "threads per worker (default: cores / workers, or 1 with "
                          "--scheduler)")
    run.add_argument("--chunk-size", type=_int_arg("--chunk-size"), metavar="C",
                     help="rows per Parquet file (default: the study's, or 262,144 = 4 x 65,536)")
    run.add_argument("--engine", choices=("local", "dask"), default="local",
                     help="local: numba threads in this process (default); dask: one task "
                          "per chunk on a Dask cluster (docs/cluster.md)")
    run.add_argument("--scheduler", metavar="ADDRESS",
                     help="--engine dask: join the running Dask scheduler at ADDRESS "
                          "(tcp://host:8786); --out must be storage every worker shares")
    run.add_argument("--workers", type=_int_arg("--workers"), metavar="N",
                     help="--engine dask: start a local cluster of N worker processes "
                          "(default: one per core)")
    run.add_argument("--columns", metavar="A,B,...",
                     help="store only these columns (and sample_id); overrides the study's "
                          "[output] columns")
    run.add_argument("--summary-only", action="store_true",
                     help="compute the study's [summary] (binned statistics, "
                          "_summary.parquet) without storing the rows")
    run.add_argument("--overwrite", action="store_true",
                     help="replace an existing dataset written with another config")
    run.add_argument("--tolerance", type=float, default=None, metavar="T",
                     help="the kernel's tolerance: the local error allowed per slip step, "
                          "relative to the impact's scales, 0 < T < 1 (default: the "
                          "study's [solver] tolerance, else 5e-9); part of the dataset's "
                          "config")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=cmd_run)

    check = sub.add_parser(
        "check", help="check a dataset directory against its manifest (exit 2 if not ok)",
        description="Verify that every chunk the manifest expects is present, recorded and "
                    "unchanged (size, Parquet footer, sample_id range, and the CRC-32 of "
                    "every byte), and that no other chunk file is there. Exit 0 when the "
                    "dataset is complete and consistent; 2 when it is not, or its manifest "
                    "records no checksums to verify it by (the report on "
                    "stdout, each problem on one line; on stderr one line naming the "
                    "first problem's file and what is wrong) or DIR is not a dataset.")
    check.add_argument("directory", metavar="DIR", help="dataset directory or URL")
    check.add_argument("--quick", action="store_true",
                       help="sizes and footers only (what mcbat.load checks), no checksums")
    check.set_defaults(func=cmd_check)

    rep = sub.add_parser(
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
                    "samples in data/) into DIR (default results/statcast).")
    rep.add_argument("paper", nargs="?", default="cabo2012",
                     choices=("cabo2012", "sawicki2003", "statcast"),
                     help="which reproduction (default: cabo2012); statcast: the flight "
                          "model's distances against measured Statcast distances "
                          "(docs/flight.md)")
    rep.add_argument("--out", default=None, metavar="DIR",
                     help="results directory (default: results; statcast: results/statcast)")
    rep.add_argument("--data", default=None, metavar="FILE",
                     help="statcast: a Baseball Savant CSV export (default: the samples "
                          "shipped in data/)")
    rep.add_argument("--samples", type=_int_arg("--samples"), metavar="N",
                     help="Monte Carlo samples (default: the study's)")
    rep.add_argument("--threads", type=_int_arg("--threads"), metavar="K",
                     help="kernel threads (default: all cores)")
    rep.add_argument("--overwrite", action="store_true",
                     help="replace a Monte Carlo dataset in DIR written with another sample "
                          "count or by an older mcbat, and files named like the outputs "
                          "(summary.json, figures/...) that mcbat did not write")
    rep.add_argument("--quiet", action="store_true", help="no progress bar")
    rep.set_defaults(func=cmd_reproduce)

    cal = sub.add_parser(
        "calibrate", help="find the e* (or mu, e_x) at which a study's mean matches a "
                          "measured number",
        description="With --study: solve (scipy brentq, common random numbers) for the "
                    "parameter at which the mean COLUMN of the study's first --samples rows "
                    "equals TARGET (in the column's unit: a drop test's exit_speed m/s, "
                    "scattering_angle deg, spin_out rad/s; a game's launch_speed mph, "
                    "launch_angle, spray_angle deg, spin_rate rpm). Without --study: the "
                    "paper's calibration (Cabo et al. Sec. V): e* such that the exit speed "
                    "at theta = pi/400 with no spin equals TARGET (m/s), with e^2 = 1 - e*^2. "
                    "Prints JSON.")
    cal.add_argument("--target", type=float, default=None, metavar="TARGET",
                     help="the measured mean (without --study: the exit speed, m/s; default "
                          "the paper's 1.44629)")
    cal.add_argument("--study", metavar="STUDY.toml", help="the study to calibrate")
    cal.add_argument("--column", default=None,
                     help="the observable whose mean is matched (default: exit_speed, or "
                          "launch_speed for a game study)")
    cal.add_argument("--parameter", default="e", help="e (default), mu or e_x")
    cal.add_argument("--samples", type=int, default=None,
                     help="rows averaged (default: the study's samples, at most 20000)")
    cal.set_defaults(func=cmd_calibrate)

    syn = sub.add_parser(
        "synth", help="draw a noisy synthetic measurement table from the model",
        description="Sample the study's setup and nuisance scatter, solve with the given e* "
                    "and mu, and add measurement noise: the kind of table an experiment "
                    "produces (format: mcbat/stats/measurements.py).")
    syn.add_argument("--study", required=True, metavar="S.toml")
    syn.add_argument("--rows", type=_int_arg("--rows"), default=60, metavar="N")
    syn.add_argument("--seed", type=_int_arg("--seed"), default=0, metavar="S")
    syn.add_argument("--e", type=float, default=None, help="energetic restitution e*")
    syn.add_argument("--mu", type=float, default=None, help="friction coefficient")
    syn.add_argument("--e-x", type=float, default=None, dest="e_x",
                     help="tangential restitution e_x (Cross & Nathan 2006; default: the "
                          "study's, 0 if unset = rigid)")
    syn.add_argument("--speed-noise", type=float, default=None,
                     help="relative 1-sigma error of the exit (launch) speed (default 0.05; "
                          "a game study: 0.01)")
    syn.add_argument("--angle-noise", type=float, default=None,
                     help="1-sigma error of the scattering angle (a game's launch and spray "
                          "angles), deg (default 3; a game study: 1)")
    syn.add_argument("--spin-noise", type=float, default=0.10,
                     help="relative 1-sigma error of the outgoing spin (default 0.10)")
    syn.add_argument("--impact-parameter-noise", type=float, default=0.0, metavar="M",
                     help="1-sigma error of the written impact parameter, m (default 0: "
                          "exact); adds an impact_parameter_err column")
    syn.add_argument("--spin-in-noise", type=float, default=0.0, metavar="RAD_S",
                     help="1-sigma error of the written incoming spin, rad/s (default 0); "
                          "adds a spin_in_err column")
    syn.add_argument("--input-noise", action="append", default=[], metavar="NAME=SIGMA",
                     help="1-sigma error of a written measured input, in the table's unit "
                          "(a game: pitch_speed, bat_speed in mph, attack_angle in deg, "
                          "undercut in m); adds a NAME_err column; repeatable")
    syn.add_argument("--out", metavar="M.csv", help="output file, .csv or .parquet "
                     "(default: stdout)")
    syn.set_defaults(func=cmd_synth)

    fit = sub.add_parser(
        "fit", help="fit model parameters to a measurement table",
        description="Maximum-likelihood fit of the free parameters (any of e, mu, "
                    "ball_inertia_factor, axial, e_x) to a measurement table, with the "
                    "study's nuisance scatter and the errors of measured inputs "
                    "(impact_parameter_err, spin_in_err) marginalised by the kernel; "
                    "profile-likelihood intervals (asymmetric; one-sided 95 % limits where "
                    "the data bound a parameter on one side only), the curvature error, and "
                    "--bootstrap N refits; chi2/dof and its p-value. "
                    "Then a model comparison: the rigid model (e_x = 0) against tangential "
                    "compliance (e_x free, Cross & Nathan 2006), by BIC, with AIC and the "
                    "likelihood ratio.")
    fit.add_argument("--study", default=None, metavar="S.toml",
                     help="the study (required, but with --flight)")
    fit.add_argument("--data", default=None, metavar="M.csv",
                     help="the measurement table (required; with --flight a Baseball Savant "
                          "CSV export, default the samples shipped in data/)")
    fit.add_argument("--flight", action="store_true",
                     help="fit the flight model's drag_scale and lift_scale to the measured "
                          "distances of --data's outfield catches and home runs "
                          "(docs/flight.md)")
    fit.add_argument("--spin-model", default=None, metavar="NAME",
                     help="with --flight: the spin the balls are flown with, nathan (his "
                          "average model; default) or inferred (mcbat.inference)")
    fit.add_argument("--free", default=None,
                     help="comma-separated (default: e,mu; with --flight "
                          "drag_scale,lift_scale)")
    fit.add_argument("--bootstrap", type=_int_arg("--bootstrap"), default=0, metavar="N",
                     help="parametric bootstrap refits (default 0)")
    fit.add_argument("--intervals", choices=("profile", "curvature"), default="profile",
                     help="profile: profile-likelihood intervals and one-sided limits "
                          "(default); curvature: Hessian errors only (faster)")
    fit.add_argument("--draws", type=_int_arg("--draws"), default=None, metavar="M",
                     help="model draws per row for the nuisance scatter and the input errors "
                          "(default 48; 128 for a game study; --population: template draws "
                          "per row, default 100)")
    fit.add_argument("--seed", type=_int_arg("--seed"), default=0, metavar="S",
                     help="seed of the draws (default 0)")
    fit.add_argument("--input-prior", choices=("cover", "widen", "study"), default=None,
                     help="the range the true values of a measured input (a column with "
                          "_err) are marginalised over: cover: the study's range widened to "
                          "cover the data, with a fitted step in the prior at the study's "
                          "ends (default with the mixture likelihood); widen: the study's "
                          "range, widened only when the data reject it (default with the "
                          "gaussian one); study: refuse a table whose data reject it")
    fit.add_argument("--likelihood", choices=("mixture", "gaussian"), default=None,
                     help="each row's likelihood: mixture: the draws' average of the "
                          "measurement's density (default for a drop test); gaussian: a "
                          "normal of the draws' mean and covariance (default for a game)")
    fit.add_argument("--residuals", metavar="FIG.png", help="write a residual figure "
                     "(.png, .pdf or .svg)")
    fit.add_argument("--json", action="store_true", help="print the result as JSON")
    fit.add_argument("--no-compare", action="store_true",
                     help="skip the rigid-versus-compliant model comparison")
    pop = fit.add_argument_group("population fits (--population, docs/population.md)")
    pop.add_argument("--population", action="store_true",
                     help="fit the study's distributions (--free swing.bat_speed.mean,... "
                          "and e, mu, e_x) to the distribution of --data's batted balls")
    pop.add_argument("--bins", type=_int_arg("--bins"), default=None, metavar="N",
                     help="bins per observable (default: ~8 rows per bin, at least 5)")
    pop.add_argument("--observables", default="launch_speed,launch_angle",
                     help="binned observables (default launch_speed,launch_angle; "
                          "spray_angle too)")
    pop.add_argument("--engine", choices=("memory", "local", "dask"), default="memory",
                     help="where the template draws are solved (default memory)")
    pop.add_argument("--figure", metavar="FIG.png",
                     help="data against the fitted model: projections and the launch "
                          "speed / angle plane")
    fit.set_defaults(func=cmd_fit)

    sc = sub.add_parser(
        "statcast", help="read a Baseball Savant (Statcast) export: counts, plate speeds, "
                         "and the tidy table in mcbat's frame and units",
        description="Read a Savant pitch-level CSV export (any season; or a pybaseball "
                    "table saved as CSV/Parquet) into mcbat's tidy table (docs/statcast.md): "
                    "print the rows, seasons, pitches by type, balls in play, rows with a "
                    "distance and with bat tracking, and the plate speed and approach angles "
                    "per pitch type.")
    sc.add_argument("file", metavar="FILE", help="the export (.csv, .csv.gz or .parquet)")
    sc.add_argument("--json", action="store_true", help="print one JSON object")
    sc.add_argument("--out", metavar="TABLE.parquet", help="write the tidy table (Parquet, "
                    "units in the schema metadata)")
    sc.set_defaults(func=cmd_statcast)

    inf = sub.add_parser(
        "infer", help="infer the spin of a Statcast export's balls in play",
        description="Read a Savant export (or mcbat's tidy table), infer each ball in "
                    "play's contact and spin through the game model under the default "
                    "assumptions (docs/spin_inference.md), print the counts.")
    inf.add_argument("file", metavar="FILE", help="the export (.csv, .csv.gz or .parquet)")
    inf.add_argument("--out", metavar="TABLE.parquet",
                     help="write the balls and their inferred contact and spin (Parquet)")
    inf.set_defaults(func=cmd_infer)

    cmp = sub.add_parser(
        "compare", help="a simulated dataset against measured rows: per-column and "
                        "launch-plane two-sample statistics",
        description="Compare DATASET (mcbat run) with MEASURED (a Baseball Savant export, its "
                    "balls in play; a CSV or Parquet table in the dataset's column names; "
                    "or another dataset; several are concatenated) on their shared columns: "
                    "Kolmogorov-Smirnov distance and p-value, Wasserstein distance, energy "
                    "distance with a permutation p-value, and the energy distance in the "
                    "launch speed / launch angle plane (docs/compare.md).")
    cmp.add_argument("dataset", metavar="DATASET", help="the simulated dataset directory")
    cmp.add_argument("measured", metavar="MEASURED", nargs="+",
                     help="measured table(s): .csv, .csv.gz, .parquet, or a dataset directory")
    cmp.add_argument("--columns", metavar="A,B,...",
                     help="compare only these columns (default: every shared column of a "
                          "physical unit)")
    cmp.add_argument("--units", action="append", default=[], metavar="COLUMN=UNIT",
                     help="the unit of a measured column the table does not state (a CSV "
                          "states none: its columns are read in the dataset's units); "
                          "repeatable")
    cmp.add_argument("--permutations", type=_int_arg("--permutations"), default=1000,
                     metavar="N", help="relabellings of each permutation test (default "
                                       "1000: p-values to 1/1001)")
    cmp.add_argument("--seed", type=_int_arg("--seed"), default=0, metavar="S",
                     help="seed of the permutations and subsamples (default 0)")
    cmp.add_argument("--max-rows", type=_int_arg("--max-rows"), default=20000, metavar="N",
                     help="rows a side in a column's energy test, subsampled beyond "
                          "(default 20000)")
    cmp.add_argument("--plane-rows", type=_int_arg("--plane-rows"), default=2000,
                     metavar="N", help="rows a side in the plane's test (default 2000, at "
                                       "most 5000)")
    cmp.add_argument("--figure", metavar="FIG.png", help="write the figure (.png, .pdf or "
                     ".svg)")
    cmp.add_argument("--json", action="store_true", help="print one JSON object")
    cmp.set_defaults(func=cmd_compare)
    return parser


def _int_arg(flag):
    def parse(text):
        try:
            return int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{flag} must be an integer, got {text!r}") \
                from None
    return parse


def main(argv=None) -> int:
    """Run the ``mcbat`` command with ``argv`` (default: ``sys.argv[1:]``); returns the exit
    code (0 ok, 2 user error or a dataset ``mcbat check`` finds not ok, 1 internal error,
    4 the environment failed mid-run, 130 interrupted, 141 broken pipe)."""
    parser = build_parser()
    debug = "--debug" in (sys.argv[1:] if argv is None else argv)
    try:
        args = parser.parse_args(argv)
        if not getattr(args, "func", None):
            parser.print_help(sys.stderr)
            return EXIT_USER
        return args.func(args)
    except _UsageError as err:
        print(f"mcbat: error: {_one_line(str(err))}", file=sys.stderr)
        return EXIT_USER
    except BrokenPipeError:
        # The reader went away (`mcbat impact ... | head -1`): stop quietly, as a command
        # killed by SIGPIPE would, and keep Python from complaining at exit.
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except KeyboardInterrupt:
        print("mcbat: interrupted; complete chunk files are kept, rerun the same command "
              "to resume", file=sys.stderr)
        return 130
    except Exception as err:  # noqa: BLE001 - the CLI boundary maps errors to exit codes
        if debug:
            import traceback

            traceback.print_exc()
        if isinstance(err, InputError):
            print(f"mcbat: error: {_one_line(str(err))}", file=sys.stderr)
            return EXIT_USER
        if isinstance(err, EnvironmentFailure):
            print(f"mcbat: error: {_one_line(str(err))}", file=sys.stderr)
            return EXIT_ENVIRONMENT
        print(f"mcbat: internal error: {type(err).__name__}: {_one_line(str(err))}"
              + ("" if debug else " (run with --debug for a traceback)"), file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
