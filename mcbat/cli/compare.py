"""``mcbat compare``: a simulated dataset against measured rows."""

from __future__ import annotations

from pathlib import Path

from mcbat.cli.common import (
    EXIT_OK,
    JSON,
    Command,
    arg,
    as_flags,
    check_figure,
    check_input_file,
    flags,
    int_option,
    note_left_out,
    print_json,
    switch,
)
from mcbat.errors import InputError, Metavar

__all__ = ["COMMAND", "COMPARE_PARAMETERS", "cmd_compare"]


COMPARE_PARAMETERS = ("permutations", "seed", "max_rows", "plane_rows", "columns", "units",
                      "strict", "by", "drawn")


def cmd_compare(args) -> int:
    """Compare the dataset with the measured tables; print the statistics."""
    from mcbat.stats.compare.comparison import (
        check_settings,
        compare,
        fig_compare,
        read_measured,
        read_simulated,
    )

    check_figure(args.figure, "--figure")
    for path in (args.dataset, *args.measured):  # before the readers' imports (seconds)
        if "://" not in path and not Path(path).exists():
            raise InputError(None, "no such file or directory", path)
        if "://" not in path and not Path(path).is_dir():
            check_input_file(path)  # a device or a FIFO would never end or block
    units = {}
    for item in args.units:
        name, sep, unit = (part.strip() for part in item.partition("="))
        if not (sep and name and unit):
            raise InputError("--units", f"expected COLUMN=UNIT, got {item!r}")
        units[name] = unit
    columns = None if args.columns is None else \
        [c.strip() for c in args.columns.split(",") if c.strip()]
    with flags(*COMPARE_PARAMETERS):
        check_settings(args.permutations, args.seed, args.max_rows, args.plane_rows, units)
        if columns == []:
            raise InputError("columns", "no column given")
    by = _parse_by(args.by)
    simulated = read_simulated(args.dataset)
    with flags(*COMPARE_PARAMETERS):
        measured = read_measured(args.measured, units, strict=args.strict)
    try:
        result = compare(simulated, measured, columns, permutations=args.permutations,
                         seed=args.seed, max_rows=args.max_rows, plane_rows=args.plane_rows,
                         by=by, drawn=args.drawn)
    except InputError as err:  # a column's problem: name the measured table(s)
        err = as_flags(_units_as_flag_values(err), COMPARE_PARAMETERS)
        where = args.dataset if "of the simulated dataset" in err.message else \
            ", ".join(args.measured)
        raise InputError(err.field, err.message, err.source or where) from None
    result.simulated = {"path": args.dataset, "rows": len(simulated),
                        "study": simulated.attrs.get("mcbat", {}).get("study_name")}
    result.measured = {"rows": len(measured), "sources": measured.attrs["sources"]}
    if args.figure:
        fig_compare(args.figure, simulated, measured, result)
    if args.json:
        out = result.to_dict()
        if args.figure:
            out["figure"] = args.figure
        print_json(out)
        _note_left_out(measured)
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
    _note_left_out(measured)
    return EXIT_OK


def _parse_by(text):
    """``--by COLUMN[:E1,E2,...]`` -> ``(column, edges or None)``, or None."""
    if text is None:
        return None
    name, _, edges = (part.strip() for part in text.partition(":"))
    if not name:
        raise InputError("--by", f"expected COLUMN or COLUMN:E1,E2,..., got {text!r}")
    if not edges:
        return name, None
    try:
        return name, [float(e) for e in edges.split(",")]
    except ValueError:
        raise InputError("--by", f"the bin edges must be numbers, got {edges!r}") from None


def _note_left_out(measured) -> None:
    """The measured rows left out, per source, on stderr (each column's rows without a
    value are in the table and the JSON)."""
    for source in measured.attrs["sources"]:
        note_left_out(source["path"], source.get("left_out", {}), "pitch(es)")


def _units_as_flag_values(error: InputError) -> InputError:
    """``error`` with a mentioned ``units`` (the library's ``{column: unit}``) written as
    ``--units`` takes it, ``COLUMN=UNIT``, one flag per column (the flag repeats)."""
    units = error.mentions.get("units")
    if not isinstance(units, dict) or not units:
        return error
    value = Metavar(" --units ".join(f"{column}={unit}" for column, unit in units.items()))
    return InputError(error.field, error.template, error.source,
                      mentions={**error.mentions, "units": value})


COMMAND = Command(
    "compare", help="a simulated dataset against measured rows: per-column and "
                    "launch-plane two-sample statistics",
    description="Compare DATASET (mcbat run) with MEASURED (a Baseball Savant export, its "
                "balls in play; a CSV or Parquet table in the dataset's column names; "
                "or another dataset; several are concatenated) on their shared columns: "
                "Kolmogorov-Smirnov distance and p-value, Wasserstein distance, energy "
                "distance with a permutation p-value, and the energy distance in the "
                "launch speed / launch angle plane; with a dataset drawn from the measured "
                "pitches, each pitch's measured value ranked among its own draws (per-row "
                "calibration; docs/compare.md).",
    arguments=(
        arg("dataset", metavar="DATASET", help="the simulated dataset directory"),
        arg("measured", metavar="MEASURED", nargs="+",
            help="measured table(s): .csv, .csv.gz, .parquet, or a dataset directory"),
        arg("--columns", metavar="A,B,...",
            help="compare only these columns (default: every shared column of a physical "
                 "unit)"),
        arg("--units", action="append", default=[], metavar="COLUMN=UNIT",
            help="the unit of a measured column the table does not state (a CSV states "
                 "none: its columns are read in the dataset's units); repeatable"),
        int_option("--permutations", default=1000, metavar="N",
                   help="relabellings of each permutation test (default 1000: p-values to "
                        "1/1001)"),
        int_option("--seed", default=0, metavar="S",
                   help="seed of the permutations and subsamples (default 0)"),
        int_option("--max-rows", default=20000, metavar="N",
                   help="rows a side in a column's energy test, subsampled beyond (default "
                        "20000)"),
        int_option("--plane-rows", default=2000, metavar="N",
                   help="rows a side in the plane's test (default 2000, at most 5000)"),
        arg("--figure", metavar="FIG.png", help="write the figure (.png, .pdf or .svg)"),
        JSON,
        switch("--strict", "refuse a Statcast export's pitch given twice instead of dropping "
               "the copy and counting it"),
        switch("--drawn", "compare only the measured pitches the dataset drew (a study's "
               "own rows of the export: without the balls in play its filters left out)"),
        arg("--by", metavar="COLUMN[:E1,E2,...]",
            help="with a dataset drawn from the measured pitches: the per-row judgement by "
                 "bins of a measured column (inner edges, e.g. bat_speed:65,70,75,80; "
                 "default its quintiles)"),
    ),
    run=cmd_compare)
