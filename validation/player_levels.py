"""Each player's contact (``[pitches.player_levels]``) judged file by file: the shipped
study with and without the players' levels on one-player exports (and any other), out of
sample. Per file: the model's mean launch speed and angle less the measured, and the KS
tests' p-values, both ways, printed and drawn; and, beside them, the same with each level
taken in sample (over all the player's balls, the judged ball's own game included), which
no study does: what leaving the game out costs.

    NUMBA_NUM_THREADS=2 .venv/bin/python -m validation player_levels \\
        statcast_2024_skubal.csv statcast_2024_ohtani.csv \\
        --figure docs/figures/bat_tracking/player_levels.png

Files are names in ``../shared/data/statcast/`` or ``data/``, or paths (``validation
bat_tracking``'s ``resolve``). The contact is the shipped study's; for files whose balls
the season sample may hold, fit it again without them first (``validation season_sample
--fit ... --judge``), which this command does not do.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import validation.bat_tracking as bt
from mcbat.runner.player_levels import estimate_levels

IN_ALL = False  # (it needs exports with bat tracking)
QUICK_ARGS = ["statcast_2024_ohtani.csv"]


def judged(names, samples: int, seed: int) -> list[dict]:
    """Per file: its label and the judgement with the league's contact and with the
    players' levels."""
    out = []
    with_levels = bt.study_definition()
    league = bt.study_definition()
    league["pitches"].pop("player_levels", None)
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            table = bt.tracked([name])
            out.append({"file": Path(name).name, "rows": len(table),
                        "league": bt.judge(league, table, samples, seed, tmp),
                        "levels": bt.judge(with_levels, table, samples, seed, tmp),
                        "in_sample": in_sample(with_levels, table, samples, seed, tmp)})
    return out


def in_sample(data, table, samples, seed, workdir) -> dict:
    """The judgement with every level taken over all the player's balls (in sample)."""
    study = bt._study(data, table, workdir)  # (its levels replaced: the league's predicts)
    spread, shift = estimate_levels(study, own_game=True)["contact"]
    sim = bt.draws(study.with_pitch_table(study.pitch_table).with_player_contact(
        spread, shift), samples, seed)
    return bt.evaluate(table, sim)


def lines(results) -> list[str]:
    """The table of gaps and p-values."""
    rows = ["| export | rows | mean launch speed, model - measured (mph): league / levels | "
            "mean launch angle (deg): league / levels | KS p launch speed: league / levels | "
            "KS p launch angle: league / levels | levels in sample: KS launch speed / angle "
            "(p) |", "|---|---|---|---|---|---|---|"]
    for r in results:
        gap = {k: {q: r[k]["means"][q][1] - r[k]["means"][q][0]
                   for q in ("launch_speed", "launch_angle")} for k in ("league", "levels")}
        rows.append(
            f"| {r['file']} | {r['rows']} | {gap['league']['launch_speed']:+.1f} / "
            f"{gap['levels']['launch_speed']:+.1f} | {gap['league']['launch_angle']:+.1f} / "
            f"{gap['levels']['launch_angle']:+.1f} | "
            f"{r['league']['ks_launch_speed_p']:.3f} / {r['levels']['ks_launch_speed_p']:.3f} | "
            f"{r['league']['ks_launch_angle_p']:.3f} / {r['levels']['ks_launch_angle_p']:.3f} | "
            f"{r['in_sample']['ks_launch_speed']:.3f} ({r['in_sample']['ks_launch_speed_p']:.2f})"
            f" / {r['in_sample']['ks_launch_angle']:.3f} "
            f"({r['in_sample']['ks_launch_angle_p']:.2f}) |")
    return rows


def figure(results, path) -> None:
    """The mean gaps and the KS p-values per file, the league's contact against the
    players' levels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    labels = [r["file"].replace("statcast_", "").replace(".csv", "") for r in results]
    y = np.arange(len(results))
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 0.45 * len(results) + 3.2), sharey=True)
    style = {"league": ("o", "tab:gray", "league's contact"),
             "levels": ("D", "tab:blue", "players' levels (other games)")}
    for k, (marker, colour, label) in style.items():
        for ax, q, unit in ((axes[0], "launch_speed", "mph"), (axes[1], "launch_angle", "deg")):
            gap = [r[k]["means"][q][1] - r[k]["means"][q][0] for r in results]
            ax.plot(gap, y, marker, color=colour, label=label, ms=6, ls="none")
            ax.set_xlabel(f"mean {q.replace('_', ' ')}, model - measured ({unit})")
        for q, dy, face in (("launch_speed", -0.15, colour), ("launch_angle", 0.15, "none")):
            p = [max(r[k][f"ks_{q}_p"], 1e-4) for r in results]
            axes[2].plot(p, y + dy, marker, color=colour, mfc=face, ms=6, ls="none",
                         label=f"{label}, {q.replace('_', ' ')}")
    for ax in axes[:2]:
        ax.axvline(0.0, color="k", lw=0.8)
    axes[2].axvline(0.05, color="tab:red", lw=0.8, ls="--")
    axes[2].set_xscale("log")
    axes[2].set_xlabel("KS test p-value (filled: launch speed, open: angle)")
    axes[0].set_yticks(y, labels)
    axes[0].invert_yaxis()
    for ax, columns in ((axes[0], 1), (axes[2], 2)):
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8,
                  ncol=columns, frameon=False)
    fig.suptitle("One-player files, out of sample: the league's contact and each player's "
                 "own (100,000 draws)")
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation player_levels",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="Savant exports with bat tracking")
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--seed", type=int, default=2025)
    parser.add_argument("--figure", help="write the figure to this PNG")
    args = parser.parse_args(argv)
    results = judged(args.files, args.samples, args.seed)
    print("\n".join(lines(results)))
    if args.figure:
        figure(results, args.figure)
        print(f"figure: {args.figure}")


if __name__ == "__main__":
    main()
