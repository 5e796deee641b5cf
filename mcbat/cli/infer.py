"""``mcbat infer``: the spin of a Statcast export's balls in play, inferred."""

from __future__ import annotations

import re

from mcbat.cli.common import (
    EXIT_OK,
    EXPORT,
    STRICT,
    TABLE_FORMATS,
    Command,
    arg,
    check_input_file,
    check_output,
    note_left_out,
    read_export,
    writing,
)
from mcbat.errors import InputError

__all__ = ["COMMAND", "cmd_infer"]


def cmd_infer(args) -> int:
    """Infer the spin of the export's balls in play; print the counts."""
    from mcbat.inference import infer_spin, write
    from mcbat.inference.columns import INPUT_COLUMNS
    from mcbat.inference.compare import LAUNCH_ANGLES, NATHAN_SLOPE, backspin_slopes
    from mcbat.statcast import balls_in_play

    check_output(args.out, "--out", TABLE_FORMATS)
    check_input_file(args.file)
    pitches, lines = read_export(args.file, args.strict, lines=True)
    bip = balls_in_play(pitches)
    balls = pitches[bip]
    try:
        spin = infer_spin(balls)
    except InputError as err:
        raise _at_file_line(err, args.file, None if lines is None else lines[bip]) from None
    counts = spin.attrs["status_counts"]
    if len(balls) and counts.get("missing_input", 0) == len(balls):
        raise _nothing_to_infer(balls, args.file, INPUT_COLUMNS)
    if args.out:
        with writing(args.out):
            write(balls, spin, args.out)
    counts = ", ".join(f"{k} {v:,}" for k, v in counts.items() if v)
    ok = spin["inference_status"] == "converged"
    print(f"{args.file}: {len(balls):,} balls in play: {counts or 'none'}")
    reasons = {k: v for k, v in spin.attrs.get("unusable_swing", {}).items() if v}
    if reasons:
        print("  unusable swings: " + ", ".join(f"{k} {v:,}" for k, v in reasons.items()))
    planes = spin.attrs.get("swing_plane", 0)
    if planes:
        print(f"  vertical bat angle from the measured swing plane (swing_path_tilt) on "
              f"{planes:,} balls, assumed on the others")
    behind = int((ok & ~spin["spray_observed"]).sum())
    if behind:
        print(f"  {behind:,} ball{'s' if behind > 1 else ''} fielded behind the plate's line "
              "(spray angle beyond 90 deg) solved with a straightaway launch "
              "(spray_observed)")
    inferred = ok & (spin["inferred"] == "bat_speed")
    if inferred.any():
        from mcbat.core.units import M_PER_IN
        from mcbat.inference import SpinAssumptions

        print(f"  bat speed inferred on {int(inferred.sum()):,} balls without a measured "
              f"swing: median {spin.loc[inferred, 'bat_speed'].median():.1f} mph, the "
              f"contact assumed {SpinAssumptions().from_barrel_end / M_PER_IN:.1f} in from the "
              "barrel end (docs/spin_inference.md)")
    moved = spin["bat_speed_adjustment"].fillna(0.0) != 0.0
    if moved.any():
        adj = spin.loc[moved, "bat_speed_adjustment"]
        print(f"  measured bat speed moved on {int(moved.sum()):,} balls (median "
              f"{adj.median():+.1f} mph, largest {adj.abs().max():.1f} mph; see "
              "bat_speed_adjustment)")
    if ok.any():
        print(f"  median backspin {spin.loc[ok, 'backspin'].median():.0f} rpm, spin rate "
              f"{spin.loc[ok, 'spin_rate'].median():.0f} rpm (assumptions: "
              "docs/spin_inference.md)")
    slopes = backspin_slopes(balls, spin)
    if slopes is not None:
        low, high = LAUNCH_ANGLES
        print(f"  backspin rises {slopes.inferred:.0f} rpm per degree of launch angle over "
              f"{low:.0f}-{high:.0f} deg ({slopes.balls:,} balls; Nathan's average model on "
              f"the same balls: {slopes.nathan_same_balls:.0f}); with the spray angle held "
              f"{slopes.inferred_spray_held:.0f} (Nathan's: {NATHAN_SLOPE:.0f})")
    if args.out:
        print(f"  written: {args.out}")
    note_left_out(args.file, {**pitches.attrs["statcast"].get("left_out", {}),
                              "not in play": int((~bip).sum())}, "pitch(es)")
    return EXIT_OK


_ROW = re.compile(r"\bin row (\d+)\b")


def _at_file_line(error, path, lines):
    """``error`` (about row ``i`` of the balls in play, from 0) located in ``path``: the
    row named by its line in the file (a CSV export) or its row among the balls (from
    1)."""
    def where(match):
        i = int(match.group(1))
        if lines is not None and 0 <= i < len(lines):
            return f"at line {int(lines[i])}"
        return f"in ball in play {i + 1}"

    return InputError(error.field, _ROW.sub(where, error.message), error.source or path)


def _nothing_to_infer(balls, path, required):
    """The error of an export whose every ball in play lacks an input of the inference:
    naming the columns empty in every ball (the plate speed and approach angles come from
    vx0, vy0, vz0, ax, ay, az)."""
    empty = [c for c in required if c in balls.columns and c != "handedness"
             and balls[c].isna().all()]
    derived = {"pitch_speed", "vertical_approach_angle", "horizontal_approach_angle"}
    plate = [c for c in empty if c in derived]
    named = ", ".join([*(c for c in empty if c not in derived),
                       *([f"{', '.join(plate)} (computed from vx0, vy0, vz0, ax, ay, az)"]
                         if plate else [])]) or "a required column"
    return InputError(None, f"none of the {len(balls):,} balls in play can be inferred: "
                      f"{named} missing in every one", path)


COMMAND = Command(
    "infer", help="infer the spin of a Statcast export's balls in play",
    description="Read a Savant export (or mcbat's tidy table), infer each ball in "
                "play's contact and spin through the game model under the default "
                "assumptions (docs/spin_inference.md), print the counts.",
    arguments=(
        EXPORT,
        arg("--out", metavar="TABLE.parquet|TABLE.csv",
            help="write the balls and their inferred contact and spin (Parquet; or CSV, "
                 "units in the column header)"),
        STRICT,
    ),
    run=cmd_infer)
