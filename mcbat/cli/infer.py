"""``mcbat infer``: the spin of a Statcast export's balls in play, inferred."""

from __future__ import annotations

from mcbat.cli.common import EXIT_OK, check_output
from mcbat.errors import InputError

__all__ = ["add_parser", "cmd_infer"]


def add_parser(sub) -> None:
    """Add ``mcbat infer`` to the subparsers ``sub``."""
    inf = sub.add_parser(
        "infer", help="infer the spin of a Statcast export's balls in play",
        description="Read a Savant export (or mcbat's tidy table), infer each ball in "
                    "play's contact and spin through the game model under the default "
                    "assumptions (docs/spin_inference.md), print the counts.")
    inf.add_argument("file", metavar="FILE", help="the export (.csv, .csv.gz or .parquet)")
    inf.add_argument("--out", metavar="TABLE.parquet",
                     help="write the balls and their inferred contact and spin (Parquet)")
    inf.set_defaults(func=cmd_infer)


def cmd_infer(args) -> int:
    """Infer the spin of the export's balls in play; print the counts."""
    from mcbat.inference import infer_spin, write
    from mcbat.statcast import balls_in_play, read

    if args.out:
        check_output(args.out, "--out", (".parquet", ".pq"))
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
    reasons = {k: v for k, v in spin.attrs.get("unusable_swing", {}).items() if v}
    if reasons:
        print("  unusable swings: " + ", ".join(f"{k} {v:,}" for k, v in reasons.items()))
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
    if args.out:
        print(f"  written: {args.out}")
    return EXIT_OK
