"""Inferred backspin against launch angle on real Statcast exports, per file: the slope
of backspin on launch angle over 10-40 deg (least squares, converged balls in play)
against Nathan's average spin model (120 rpm per degree, and the model on the same balls,
whose spray angles rise with the launch angle), the launch angle's coefficient with the
spray angle held (regressed on both, as Nathan's 120 is), and the convergence of the balls with a
measured swing, with the spin averaged over the open attack angles (the default) and
with one assumed attack angle (``attack_angle_nodes = 1``); the figure.

    .venv/bin/python -m validation spin_inference_slopes \\
        --figure docs/figures/spin_vs_launch_angle_real.png

``--vertical-bat-angle DEG``, ``--spin-efficiency X`` and ``--e-x X`` (the tangential
restitution, fitted with this table: docs/spin_inference.md) change those assumptions (the
defaults: ``mcbat.inference.SpinAssumptions``), to see what the slopes owe to them.

Reads ``../shared/data/statcast/`` (relative to the repository; skipped where absent)
and the shipped ``data/`` exports.
"""

import argparse
import dataclasses
import math
from pathlib import Path

import numpy as np

from mcbat import statcast
from mcbat.inference import InferenceOptions, SpinAssumptions, infer_spin

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT / ".." / "shared" / "data" / "statcast"
FILES = (("2024, Ohtani's", SHARED / "statcast_2024_ohtani.csv"),
         ("2024, Skubal's", SHARED / "statcast_2024_skubal.csv"),
         ("2025-05-01", SHARED / "statcast_2025-05-01.csv"),
         ("2021-09-01, 10, 11", SHARED / "statcast_2021-09-01_10_11.csv"),
         ("2020-09-03 (shipped)", ROOT / "data" / "statcast_2020-09-03.csv"),
         ("2019, Darvish's (shipped)", ROOT / "data" / "statcast_2019_darvish.csv"))


def nathan_backspin(balls):
    """Nathan's average model (rpm), the spray angle in the batter's frame."""
    hand = np.where(balls["handedness"] == "L", -1.0, 1.0)
    return (-763.0 + 120.0 * balls["launch_angle"].to_numpy()
            + 21.0 * balls["spray_angle"].to_numpy() * hand)


def slope(la, spin, ok):
    sel = ok & (la >= 10) & (la <= 40) & np.isfinite(spin)
    return np.polyfit(la[sel], spin[sel], 1), int(sel.sum())


def partial_slope(balls, spin, ok, resamples=300):
    """The launch angle's coefficient of backspin regressed on launch angle *and* the
    batter-frame spray angle over 10-40 deg (rpm/deg), as Nathan's 120 is in his model
    (``nathan_backspin``), and its bootstrap standard deviation over the balls."""
    la = balls["launch_angle"].to_numpy()
    spray = balls["spray_angle"].to_numpy() * np.where(balls["handedness"] == "L", -1.0, 1.0)
    rows = np.flatnonzero(ok & (la >= 10) & (la <= 40) & np.isfinite(spin)
                          & np.isfinite(spray))

    def coefficient(i):
        design = np.column_stack([np.ones(i.size), la[i], spray[i]])
        return np.linalg.lstsq(design, spin[i], rcond=None)[0][1]

    rng = np.random.default_rng(0)
    spread = np.std([coefficient(rng.choice(rows, rows.size)) for _ in range(resamples)])
    return coefficient(rows), spread


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", help="write the figure (PNG)")
    parser.add_argument("--vertical-bat-angle", type=float, default=None,
                        help="the assumed vertical bat angle, deg (default: -30)")
    parser.add_argument("--spin-efficiency", type=float, default=None,
                        help="the pitch's assumed spin efficiency (default: 1)")
    parser.add_argument("--e-x", type=float, default=None,
                        help="the tangential restitution e_x (default: the game preset's)")
    args = parser.parse_args(argv)
    point = InferenceOptions(attack_angle_nodes=1)
    changed = {}
    if args.vertical_bat_angle is not None:
        changed["vertical_bat_angle"] = math.radians(args.vertical_bat_angle)
    if args.spin_efficiency is not None:
        changed["spin_efficiency"] = args.spin_efficiency
    if args.e_x is not None:
        changed["restitution"] = dataclasses.replace(SpinAssumptions().restitution,
                                                     e_x=args.e_x)
    assumptions = dataclasses.replace(SpinAssumptions(), **changed)
    if changed:
        print("assumptions changed: " + ", ".join(
            f"{k} = {args.vertical_bat_angle if k == 'vertical_bat_angle' else v}"
            + (" deg" if k == "vertical_bat_angle" else "") for k, v in changed.items()))
    results = []
    print("| file | balls in play | converged | slope, 10-40° (rpm/°) | intercept (rpm) | "
          "Nathan on the same balls (rpm/°) | with the spray angle held (rpm/°; Nathan: "
          "120) | one assumed attack angle: slope | tracked: converged (one attack angle) "
          "| tracked: statuses |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, path in FILES:
        if not path.is_file():
            print(f"| {label} | absent | | | | | | | | |")
            continue
        pitches = statcast.read(path)
        balls = pitches[statcast.balls_in_play(pitches)]
        out = infer_spin(balls, assumptions=assumptions)
        one = infer_spin(balls, assumptions=assumptions, options=point)
        ok = (out["inference_status"] == "converged").to_numpy()
        ok1 = (one["inference_status"] == "converged").to_numpy()
        la = balls["launch_angle"].to_numpy()
        (s, c), n = slope(la, out["backspin"].to_numpy(), ok)
        (s1, _), _ = slope(la, one["backspin"].to_numpy(), ok1)
        (sn, _), _ = slope(la, nathan_backspin(balls), ok)
        held, held_err = partial_slope(balls, out["backspin"].to_numpy(), ok)
        tracked = (balls["bat_speed"].notna().to_numpy() if "bat_speed" in balls
                   else np.zeros(len(balls), bool))
        if tracked.any():
            counts = out.loc[tracked, "inference_status"].value_counts()
            statuses = ", ".join(f"{k} {v}" for k, v in counts.items()
                                 if v and k != "converged")
            conv = (f"{ok[tracked].sum()}/{tracked.sum()} ({ok[tracked].mean():.1%}) "
                    f"({ok1[tracked].sum()}, {ok1[tracked].mean():.1%})")
        else:
            conv, statuses = "–", "–"
        print(f"| {label} | {len(balls)} | {ok.sum()} | **{s:.0f}** (n = {n}) | {c:.0f} | "
              f"{sn:.0f} | {held:.0f} ± {held_err:.0f} | {s1:.0f} | {conv} | {statuses} |")
        results.append((label, la[ok], out["backspin"].to_numpy()[ok]))
    if args.figure:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(2, 3, figsize=(13, 7.5), sharex=True, sharey=True)
        grid = np.linspace(-40, 70, 2)
        for ax, (label, la, back) in zip(axes.ravel(), results):
            ax.scatter(la, back, s=4, alpha=0.35, color="tab:blue", label="inferred")
            edges = np.arange(-40, 75, 10)
            mid = 0.5 * (edges[1:] + edges[:-1])
            med = [np.median(back[(la >= a) & (la < b)]) if ((la >= a) & (la < b)).sum() > 4
                   else np.nan for a, b in zip(edges[:-1], edges[1:])]
            ax.plot(mid, med, "o-", color="tab:blue", label="inferred, median per 10°")
            ax.plot(grid, -763 + 120 * grid, "k--", label="Nathan: −763 + 120 LA")
            sel = (la >= 10) & (la <= 40)
            if sel.sum() > 2:
                s, c = np.polyfit(la[sel], back[sel], 1)
                x = np.array([10.0, 40.0])
                ax.plot(x, c + s * x, color="tab:red", lw=2,
                        label=f"fit 10-40°: {s:.0f} rpm/°")
            ax.set_title(label, fontsize=10)
            ax.axhline(0, color="0.8", lw=0.8)
            ax.legend(fontsize=7, loc="upper left")
        for ax in axes[-1]:
            ax.set_xlabel("launch angle (deg)")
        for ax in axes[:, 0]:
            ax.set_ylabel("inferred backspin (rpm)")
        axes[0, 0].set_ylim(-8000, 10000)
        fig.suptitle("Inferred backspin of real balls in play (mcbat infer, defaults) and "
                     "Nathan's average spin model", fontsize=11)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        print(f"\nwritten: {args.figure}")


if __name__ == "__main__":
    main()
