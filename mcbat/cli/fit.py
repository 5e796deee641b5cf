"""``mcbat fit``: model parameters fitted to a measurement table; the flight model's
scales to measured distances (``--flight``); a game study's distributions to batted balls
(``--population``)."""

from __future__ import annotations

import contextlib
import re

from mcbat.cli.common import (
    EXIT_OK,
    Command,
    Group,
    arg,
    check_figure,
    check_input_file,
    flags,
    int_option,
    note_left_out,
    print_json,
    read_export,
    switch,
)
from mcbat.cli.studies import study_file
from mcbat.errors import InputError

__all__ = ["COMMAND", "cmd_fit"]


def _fit_flight(args) -> int:
    from mcbat.papers.statcast.calibrate import calibrate, check_free, hold_out
    from mcbat.papers.statcast.left_out import flight_left_out
    from mcbat.papers.statcast.reproduce import SPIN_MODELS, balls_in_their_air, read_statcast
    from mcbat.statcast import read
    from mcbat.statcast.weather import read_weather

    for flag in ("study", "residuals", "draws"):
        if getattr(args, flag) is not None:
            raise InputError(f"--{flag}", "not with --flight (the flight fit flies each "
                             "ball of --data once)")
    if args.bootstrap:
        raise InputError("--bootstrap", "not with --flight")
    spin_model = args.spin_model or "nathan"
    with flags("free", "intervals", "spin_model", "weather", "strict"):
        free = check_free(args.free)
        if spin_model not in SPIN_MODELS:
            raise InputError("spin_model", f"must be one of {', '.join(SPIN_MODELS)}, got "
                             f"{spin_model!r}")
        if args.data is not None:
            check_input_file(args.data, "--data")
        if args.weather is not None:
            check_input_file(args.weather, "--weather")
        if args.data is None:
            table, source = read_statcast(None)
        else:
            table, source = read(args.data, strict=args.strict), str(args.data)
        weather = None if args.weather is None else read_weather(args.weather)
        try:
            balls = balls_in_their_air(table, source, weather)
        except InputError as err:
            raise _unmeasured_launch(table, source) or err from None
        backspin, sidespin = SPIN_MODELS[spin_model](balls)
        result = calibrate(balls, backspin, sidespin, spin_model=spin_model, free=free,
                           intervals=args.intervals, source=source)
        result.holdout = hold_out(balls, backspin, sidespin, result, free=free)
    left_out = flight_left_out(table, balls, result.balls)
    if args.json:
        print_json({**result.to_dict(), "rows": int(len(table)), "left_out": left_out})
    else:
        print(f"fit of {', '.join(result.result.params)} to {result.balls} outfield catches "
              f"and home runs of {result.source} (flight model nathan, spin model "
              f"{result.spin_model}):")
        for line in result.lines():
            print(line)
    note_left_out(source, left_out)
    return EXIT_OK


def _unmeasured_launch(table, source):
    """When no ball is left to fly, an ``InputError`` naming the launch column the
    reader set to NaN (cells out of range or not numbers, with the first one's line), or
    None when the cause is elsewhere."""
    report = table.attrs.get("statcast", {})
    for column in ("launch_speed", "launch_angle", "hit_distance_sc"):
        for key, what in (("out_of_range", "outside the range of a measurement"),
                          ("non_numeric", "not numbers")):
            bad = report.get(key, {}).get(column)
            if bad:
                where = f"line {bad['line']}" if "line" in bad else f"row {bad.get('row')}"
                return InputError(column, f"no ball is left to fly: {bad['cells']:,} cells "
                                  f"are {what} (the first at {where}: {bad['value']})",
                                  source)
    return None


def cmd_fit(args) -> int:
    """Fit the study's free parameters to the table (or --flight, --population)."""
    try:
        return _cmd_fit(args)
    except KeyboardInterrupt:  # a fit writes no chunk files: nothing is kept to resume
        import sys

        print("mcbat: interrupted; a fit keeps no partial results: rerun the same command "
              "to start it again", file=sys.stderr)
        return 130


def _cmd_fit(args) -> int:
    from mcbat import load_study  # (a game study's [pitches] file is read too)
    from mcbat.stats.fit.estimate import check_bootstrap, fit
    from mcbat.stats.fit.likelihood import check_free
    from mcbat.stats.fit.model_choice import compare_models

    if args.flight:
        return _fit_flight(args)
    if args.weather is not None:
        raise InputError("--weather", "applies to --flight only")
    if args.population:
        return _fit_population(args)
    _check_required(args)
    free = _fit_options(args, check_free, check_bootstrap)
    check_figure(args.residuals, "--residuals")
    with study_file(args.study, "--study") as path:
        study = load_study(path)
    table, left_out = _measurement_table(args)
    with flags("free", "bootstrap", "draws", "seed", "intervals"), \
            _rows_as_lines(table.attrs.get("lines")):
        result = fit(study, table, free, bootstrap=args.bootstrap, draws=args.draws,
                     seed=args.seed, intervals=args.intervals, input_prior=args.input_prior,
                     likelihood=args.likelihood)
        comparison = None if args.no_compare else compare_models(
            study, table, free, draws=args.draws, seed=args.seed, fitted=result,
            input_prior=args.input_prior, likelihood=args.likelihood)
    if args.residuals:
        from mcbat.stats.fit.figure import fig_fit_residuals

        fig_fit_residuals(args.residuals, table, result)
    if args.json:
        out = result.to_dict()
        if comparison is not None:
            out["model_comparison"] = comparison.to_dict()
        if left_out is not None:
            out["left_out"] = left_out
        print_json(out)
    else:
        print(f"fit of {', '.join(free)} to {len(table)} rows of {args.data} "
              f"(study {study.name}):")
        for line in result.lines():
            print(line)
        print(f"  chi2 / dof = {result.chi2:.1f} / {result.dof}, p-value = "
              f"{result.p_value:.3f}")
        for warning in result.warnings:
            print(f"  note: {warning}")
        if comparison is not None:
            print("\n".join(comparison.lines()))
    if left_out is not None:
        kept = table.attrs["statcast"]
        total = kept["rows"] + sum(kept.get("left_out", {}).values())
        note_left_out(f"{args.data}: Statcast export: {kept['used']:,} of {total:,} pitches "
                      f"used (balls in play with launch speed, angle, spray and plate speed"
                      f"{' and bat tracking' if 'bat_speed' in table else ''})", left_out,
                      "pitch(es)")
    return EXIT_OK


_ROW_LIST = re.compile(r"\brows? ((?:\d+(?: \([^)]*\))?(?:, | and )?)+)")


@contextlib.contextmanager
def _rows_as_lines(lines):
    """Errors about rows of a table read from a Savant export (``row 3 (value)``, rows
    from 1) name the file's lines instead (``line 57 (value)``)."""
    try:
        yield
    except InputError as err:
        if not lines:
            raise

        def to_line(number):
            i = int(number.group(1)) - 1
            return f"{lines[i]}{number.group(2)}" if 0 <= i < len(lines) else number.group(0)

        def listed(match):
            word = "lines" if match.group(0).startswith("rows") else "line"
            return f"{word} " + re.sub(r"(\d+)( \(|,|$| and)", to_line, match.group(1))

        raise InputError(err.field, _ROW_LIST.sub(listed, err.template), err.source,
                         mentions=err.mentions) from None


def _check_required(args):
    """The options a study fit needs, and none that only --flight takes."""
    if args.spin_model is not None:
        raise InputError("--spin-model", "applies to --flight only")
    if args.study is None:
        raise InputError("--study", "required (or --flight: the flight model's drag and "
                         "lift against measured distances)")
    if args.data is None:
        raise InputError("--data", "required")


def _measurement_table(args):
    """The game fit's table of ``--data`` (a file checked first: a regular file, within
    the cap of a compressed one) and, for a Savant export, the pitches left out."""
    from mcbat.statcast import is_statcast, read
    from mcbat.statcast.files import check_expansion
    from mcbat.stats.measurements import read_measurements

    check_input_file(args.data, "--data")
    check_expansion(args.data, args.data, "--data")
    if args.strict and is_statcast(args.data):
        with flags("strict"):
            read(args.data, strict=True)  # refuses a pitch given twice
    table = read_measurements(args.data)
    return table, _statcast_left_out(table)


def _statcast_left_out(table):
    """The pitches of a Savant export a game fit leaves out, by reason (None for a
    measurement table that is not one)."""
    if "statcast" not in table.attrs:
        return None
    kept = table.attrs["statcast"]
    out = dict(kept.get("left_out", {}))
    out.update({"not in play": kept["not_in_play"], "without launch": kept["no_launch"],
                "fielded in foul territory": kept["foul_territory"],
                "without plate speed": kept["no_plate_speed"],
                "without bat tracking": kept["no_bat_tracking"]})
    return out


def _fit_population(args) -> int:
    """``mcbat fit --population``: a game study's distributions against batted balls
    (docs/population.md)."""
    from mcbat import load_study
    from mcbat.stats.population.fit import fit_population

    for flag, value in (("--study", args.study), ("--data", args.data),
                        ("--free", args.free)):
        if value is None:
            raise InputError(flag, "required with --population")
    check_figure(args.figure, "--figure")
    check_input_file(args.data, "--data")
    with study_file(args.study, "--study") as path:
        study = load_study(path)
    table = read_export(args.data, args.strict)
    with flags("free", "draws", "seed", "bins", "observables", "engine"):
        result = fit_population(study, table, [f for f in args.free.split(",") if f],
                                draws=args.draws, bins=args.bins, seed=args.seed,
                                observables=args.observables.split(","), engine=args.engine)
    if args.figure:
        from mcbat.stats.population.figure import fig_population

        fig_population(args.figure, result)
    left_out = table.attrs["statcast"].get("left_out", {})
    if args.json:
        print_json({**result.to_dict(), "left_out": left_out})
        note_left_out(args.data, left_out, "pitch(es)")
        return EXIT_OK
    note_left_out(args.data, left_out, "pitch(es)")
    print(f"population fit of {args.free} to {result.rows} batted balls of {args.data} "
          f"in {' x '.join(result.observables)} (study {study.name}; {result.draws:,} "
          f"template draws, effective {result.effective_draws:,.0f}):")
    print("\n".join(result.lines()))
    print(f"  chi2 / dof = {result.chi2:.1f} / {result.dof}, p-value = {result.p_value:.3f}")
    for warning in result.warnings:
        print(f"  note: {warning}")
    return EXIT_OK


def _fit_options(args, check_free, check_bootstrap):
    """The fit's free parameters; every option checked before any work."""
    with flags("free", "bootstrap", "draws", "seed"):
        free = tuple(check_free(args.free or "e,mu"))
        check_bootstrap(args.bootstrap)
        if args.draws is not None and args.draws < 4:
            raise InputError("draws", f"must be an integer >= 4, got {args.draws}")
        if args.seed < 0:
            raise InputError("seed", f"must be an integer >= 0, got {args.seed}")
        if args.seed > 2**63 - 1:
            raise InputError("seed", f"must be <= 2**63 - 1, got {args.seed}")
    return free


COMMAND = Command(
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
                "likelihood ratio.",
    arguments=(
        arg("--study", metavar="S.toml", help="the study (required, but with --flight)"),
        arg("--data", metavar="M.csv",
            help="the measurement table (required; with --flight a Baseball Savant CSV "
                 "export, default the samples shipped in data/)"),
        switch("--flight", "fit the flight model's drag_scale and lift_scale to the measured "
               "distances of --data's outfield catches and home runs (docs/flight.md)"),
        arg("--spin-model", metavar="NAME",
            help="with --flight: the spin the balls are flown with, nathan (his average "
                 "model; default) or inferred (mcbat.inference)"),
        arg("--weather", metavar="FILE",
            help="with --flight: a per-game weather table (docs/parks-and-weather.md; "
                 "default each park's climate normal)"),
        arg("--free", help="comma-separated (default: e,mu; with --flight "
                           "drag_scale,lift_scale)"),
        int_option("--bootstrap", default=0, metavar="N",
                   help="parametric bootstrap refits (default 0)"),
        arg("--intervals", choices=("profile", "curvature"), default="profile",
            help="profile: profile-likelihood intervals and one-sided limits (default); "
                 "curvature: Hessian errors only (faster)"),
        int_option("--draws", metavar="M",
                   help="model draws per row for the nuisance scatter and the input errors "
                        "(default 48; 128 for a game study; --population: template draws "
                        "per row, default 100)"),
        int_option("--seed", default=0, metavar="S", help="seed of the draws (default 0)"),
        arg("--input-prior", choices=("cover", "widen", "study"),
            help="the range the true values of a measured input (a column with _err) are "
                 "marginalised over: cover: the study's range widened to cover the data, "
                 "with a fitted step in the prior at the study's ends (default with the "
                 "mixture likelihood); widen: the study's range, widened only when the data "
                 "reject it (default with the gaussian one); study: refuse a table whose "
                 "data reject it"),
        arg("--likelihood", choices=("mixture", "gaussian"),
            help="each row's likelihood: mixture: the draws' average of the measurement's "
                 "density (default for a drop test); gaussian: a normal of the draws' mean "
                 "and covariance (default for a game)"),
        arg("--residuals", metavar="FIG.png",
            help="write a residual figure (.png, .pdf or .svg)"),
        switch("--json", "print the result as JSON"),
        switch("--no-compare", "skip the rigid-versus-compliant model comparison"),
        switch("--strict", "refuse a Statcast export's pitch given twice (the same game_pk, "
               "at_bat_number and pitch_number) instead of dropping the copy and counting "
               "it"),
        Group((
            switch("--population", "fit the study's distributions (--free "
                   "swing.bat_speed.mean,... and e, mu, e_x) to the distribution of --data's "
                   "batted balls"),
            int_option("--bins", metavar="N",
                       help="bins per observable (default: ~8 rows per bin, at least 5)"),
            arg("--observables", default="launch_speed,launch_angle",
                help="binned observables (default launch_speed,launch_angle; spray_angle "
                     "too, and hit_distance (Statcast's hit_distance_sc) for a study with "
                     "[flight])"),
            arg("--engine", choices=("memory", "local", "dask"), default="memory",
                help="where the template draws are solved (default memory)"),
            arg("--figure", metavar="FIG.png",
                help="data against the fitted model: projections and the launch speed / "
                     "angle plane"),
        ), title="population fits (--population, docs/population.md)"),
    ),
    run=cmd_fit)
