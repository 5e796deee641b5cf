"""``mcbat statcast``: a Baseball Savant export read, summarised, and written as mcbat's
tidy table."""

from __future__ import annotations

import re

from mcbat.cli.common import (
    EXIT_OK,
    EXPORT,
    JSON,
    STRICT,
    TABLE_FORMATS,
    Command,
    arg,
    check_output,
    note_left_out,
    print_json,
    read_export,
    writing,
)

__all__ = ["COMMAND", "cmd_statcast", "statcast_lines"]


def cmd_statcast(args) -> int:
    """Read the export; print its summary (or JSON), write the tidy table with --out."""
    from mcbat.dataset.tables import write_table
    from mcbat.statcast import summarize, write

    check_output(args.out, "--out", TABLE_FORMATS)
    table = read_export(args.file, args.strict)
    summary = summarize(table)
    if args.out:
        with writing(args.out):
            if str(args.out).lower().endswith(".csv"):
                write_table(table, args.out, field="--out")
            else:
                write(table, args.out)
        summary["out"] = args.out
    if args.json:
        print_json(summary)
    else:
        print("\n".join(statcast_lines(summary)))
    note_left_out(summary["source"], summary["left_out"], "pitch(es)")
    return EXIT_OK


def statcast_lines(summary):
    """The summary of ``mcbat statcast`` as text lines."""
    seasons = ", ".join(str(y) for y in summary["seasons"]) or "none"
    types = ", ".join(f"{_code(k)} {v:,}" for k, v in summary["pitch_types"].items())
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
        lines.append(f"  {_code(kind)} at the plate (median): {parts[0]} mph, vertical approach "
                     f"{parts[1]} deg, horizontal {parts[2]} deg")
    check = summary.get("attack_direction_check")
    if check:
        lines.append(f"  attack_direction vs spray towards the opposite field: correlation "
                     f"{check['correlation']:+.2f} over {check['rows']:,} balls in play "
                     "(> 0: the sign convention of docs/statcast.md holds)")
    if summary.get("missing_columns"):
        lines.append(f"  columns this export lacks (NaN): {', '.join(summary['missing_columns'])}")
    for column, bad in summary.get("non_numeric", {}).items():
        where = (f" (first at line {bad['line']}: {bad['value']!r})" if "line" in bad else
                 f" (first at row {bad['row']}: {bad['value']!r})" if "row" in bad else "")
        lines.append(f"  {column}: {bad['cells']:,} non-numeric cell(s) set to NaN{where}")
    for column, far in summary.get("out_of_range", {}).items():
        where = f"line {far['line']}" if "line" in far else f"row {far['row']}"
        low, high = far["range"]
        lines.append(f"  {column}: {far['cells']:,} cell(s) outside {low:g}..{high:g} set to "
                     f"NaN (first at {where}: {far['value']})")
    if summary.get("elevation_missing"):
        teams = ", ".join(f"{k} {v:,}" for k, v in summary["elevation_missing"].items())
        unknown = ", ".join(summary.get("unknown_home_teams", {}))
        lines.append(f"  rows without a park elevation (NaN), by home_team: {teams}"
                     + (f"; not in the park table: {unknown}" if unknown else ""))
    if summary.get("duplicate_pitches"):
        dup = summary["duplicate_pitches"]
        lines.append(f"  pitches given twice, the copies left out: {dup['rows']:,} (the first "
                     f"at {dup['first']}, a copy of {dup['repeats']})")
    if summary.get("out"):
        lines.append(f"  tidy table written to {summary['out']}")
    return lines


def _code(kind):
    """A pitch type as printed: Savant's codes (FF, SL, ...: capital letters) as they
    are, anything else the file holds quoted (a cell of text that is no code)."""
    return kind if re.fullmatch(r"[A-Z]{1,3}|\(none\)", kind) else repr(kind)


COMMAND = Command(
    "statcast", help="read a Baseball Savant (Statcast) export: counts, plate speeds, "
                     "and the tidy table in mcbat's frame and units",
    description="Read a Savant pitch-level CSV export (any season; or a pybaseball "
                "table saved as CSV/Parquet) into mcbat's tidy table (docs/statcast.md): "
                "print the rows, seasons, pitches by type, balls in play, rows with a "
                "distance and with bat tracking, and the plate speed and approach angles "
                "per pitch type.",
    arguments=(
        EXPORT,
        JSON,
        arg("--out", metavar="TABLE.parquet|TABLE.csv",
            help="write the tidy table (Parquet, units in the schema metadata; or CSV, "
                 "units in the column header: launch_speed [mph])"),
        STRICT,
    ),
    run=cmd_statcast)
